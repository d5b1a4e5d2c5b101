#include "maille/limits.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace maille::limits {

std::uint64_t memory_budget_bytes() {
  if (const char* env = std::getenv("MAILLE_MEMORY_BUDGET"); env && *env) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(env, &end, 10);
    if (end && *end == '\0' && v > 0) return v;
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  std::uint64_t budget = pages <= 0 || page <= 0 ? std::uint64_t{4} << 30  // unknown: assume 8 GiB
                                                 : std::uint64_t(pages) / 2 * std::uint64_t(page);
  // Under an address-space limit (ulimit -v), half of it: beyond, an allocation fails with
  // std::bad_alloc, which inside a parallel region aborts the process.
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    budget = std::min<std::uint64_t>(budget, std::uint64_t(as.rlim_cur) / 2);
  return budget;
}

std::string check_size(const SizeEstimate& total) {
  const std::uint64_t budget = memory_budget_bytes();
  // Products are taken in double: a resolution of 2^40 must not wrap around.
  const double bytes = double(total.points) * bytes_per_point +
                       double(total.links) * bytes_per_link + double(total.faces) * bytes_per_face;
  std::ostringstream why;
  if (total.points > max_points)
    why << "more than " << max_points << " points";
  else if (total.links > max_links)
    why << "more than " << max_links << " links";
  else if (bytes > double(budget))
    why << "more than the memory budget of " << double(budget) / double(1 << 30)
        << " GiB (half the physical memory)";
  else
    return {};
  std::ostringstream s;
  s.precision(3);
  s << "the model would have " << total.points << " points and " << total.links << " links, about "
    << bytes / double(1 << 30) << " GiB: " << why.str();
  return s.str();
}

}  // namespace maille::limits
