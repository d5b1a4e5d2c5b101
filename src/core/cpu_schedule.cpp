#include "maille/detail/cpu_schedule.hpp"

#include <algorithm>
#include <tuple>

#include "maille/colouring.hpp"

namespace maille::detail {

void CpuSchedule::clear() {
  ready_ = false;
  chunk_begin_.clear();
  chunk_is_run_.clear();
  band_begin_.clear();
  band_order_.clear();
  groups_.clear();
}

void CpuSchedule::release_scratch() {
  for (auto* v : {&order_, &run_, &offsets_, &idx_, &colouring_.order, &colouring_.offsets,
                  &colour_scratch_.colour, &colour_scratch_.pending, &colour_scratch_.later})
    std::vector<std::uint32_t>().swap(*v);
  std::vector<std::uint64_t>().swap(colour_scratch_.used);
}

std::span<const std::uint32_t> CpuSchedule::order(std::span<const LinkEnds> ends, bool by_reach) {
  clear();
  std::uint32_t lo = ~0u, hi = 0;
  for (const auto& e : ends) lo = std::min(lo, e.a), hi = std::max(hi, e.a);
  band_origin_ = ends.empty() ? 0 : lo;
  const std::uint32_t span = ends.empty() ? 1 : hi - lo + 1;
  band_points_ = std::max(kMinBandPoints, (span + kBands - 1) / kBands);
  std::vector<std::uint32_t>& order = order_;
  order.resize(ends.size());
  for (std::size_t l = 0; l < order.size(); ++l) order[l] = static_cast<std::uint32_t>(l);
  // The link's own position last: the order of a stable sort, without std::stable_sort's
  // temporary buffer (an allocation at every call).
  auto key = [&](std::uint32_t l) {
    const std::int64_t reach = by_reach ? std::int64_t(ends[l].b) - ends[l].a : 0;
    return std::tuple{band_of(ends[l].a), reach, ends[l].a, l};
  };
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t i, std::uint32_t j) { return key(i) < key(j); });
  return order;
}

void CpuSchedule::build(std::span<const LinkEnds> ends, std::uint32_t point_count) {
  cut_chunks(ends);
  std::vector<std::uint32_t>& offsets = offsets_;
  std::vector<std::uint32_t>& idx = idx_;
  offsets.assign(band_begin_.size(), 0);
  idx.clear();
  idx.reserve(ends.size() * 2);
  for (std::size_t b = 0; b + 1 < band_begin_.size(); ++b) {
    for (std::size_t l = chunk_begin_[band_begin_[b]]; l < chunk_begin_[band_begin_[b + 1]]; ++l) {
      idx.push_back(ends[l].a);
      idx.push_back(ends[l].b);
    }
    offsets[b + 1] = static_cast<std::uint32_t>(idx.size());
  }
  colour_sets(offsets, idx, point_count, colouring_, colour_scratch_);
  band_order_.swap(colouring_.order);
  groups_.swap(colouring_.offsets);
  ready_ = true;
}

// Cuts each band into chunks: a run (both ends advance by one, at least kMinRun links, at most
// kChunk) or up to kChunk other links. run[l]: links from l on that continue l's run.
void CpuSchedule::cut_chunks(std::span<const LinkEnds> ends) {
  const std::size_t n = ends.size();
  std::vector<std::uint32_t>& run = run_;
  run.assign(n + 1, 0);
  for (std::size_t l = n; l-- > 0;) {
    const bool next = l + 1 < n && ends[l + 1].a == ends[l].a + 1 &&
                      ends[l + 1].b == ends[l].b + 1 &&
                      band_of(ends[l + 1].a) == band_of(ends[l].a);
    run[l] = next ? run[l + 1] + 1 : 1;
  }
  chunk_begin_.assign(1, 0);
  chunk_is_run_.clear();
  band_begin_.assign(1, 0);
  for (std::size_t l = 0; l < n;) {
    const std::uint32_t band = band_of(ends[l].a);
    std::size_t end = l;
    const bool is_run = run[l] >= kMinRun;
    if (is_run) {
      end = l + std::min<std::size_t>(run[l], kChunk);
    } else {
      while (end < n && end - l < kChunk && band_of(ends[end].a) == band &&
             (end == l || run[end] < kMinRun))
        ++end;
    }
    chunk_begin_.push_back(static_cast<std::uint32_t>(end));
    chunk_is_run_.push_back(is_run);
    l = end;
    if (l == n || band_of(ends[l].a) != band)
      band_begin_.push_back(static_cast<std::uint32_t>(chunk_is_run_.size()));
  }
}

}  // namespace maille::detail
