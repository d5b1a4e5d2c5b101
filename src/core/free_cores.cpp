#include "free_cores.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "maille/cores.hpp"

namespace maille::detail {

int free_cores_from(int cores, std::span<const int> running) {
  if (running.empty()) return cores;
  const int others = *std::min_element(running.begin(), running.end()) - 1;  // not this one
  return std::clamp(cores - std::max(others, 0), 1, std::max(cores, 1));
}

namespace {

int procs_running() {
  std::ifstream in("/proc/stat");
  std::string key;
  while (in >> key) {
    if (key == "procs_running") {
      int n = -1;
      in >> n;
      return n;
    }
    in.ignore(1 << 20, '\n');
  }
  return -1;
}

}  // namespace

int free_cores(int cores) {
  if (cores <= 1) return 1;
  std::vector<int> samples;
  for (int k = 0; k < 5; ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const int n = procs_running();
    if (n < 1) return cores;  // not Linux, or no /proc: trust the core count
    samples.push_back(n);
  }
  return free_cores_from(cores, samples);
}

}  // namespace maille::detail

namespace maille {

int cores_available() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return std::max(CPU_COUNT(&set), 1);
}

int free_cores_now() {
  return detail::free_cores(cores_available());
}

void wait_passively_when_cores_are_shared(char** argv, bool renders_itself) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (!renders_itself && free_cores_now() >= cores_available()) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: then go on as we are
  unsetenv("OMP_WAIT_POLICY");
}

}  // namespace maille
