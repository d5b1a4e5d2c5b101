#include "free_cores.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "maille/cores.hpp"

namespace maille::detail {

int free_cores_from(int cores, std::span<const int> running) {
  if (running.empty()) return cores;
  const int others = *std::min_element(running.begin(), running.end()) - 1;  // not this one
  return std::clamp(cores - std::max(others, 0), 1, std::max(cores, 1));
}

// Read with read(2) into a fixed buffer and scanned a character at a time, never a stream: the
// simulator asks during a run (follow_cores.hpp), where the step allocates nothing, and the
// line sits after /proc/stat's long ones (intr), past any fixed-size window.
int runnable_tasks() {
  const int fd = ::open("/proc/stat", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  static constexpr char kKey[] = "\nprocs_running ";
  constexpr std::size_t kKeyLength = sizeof kKey - 1;
  std::size_t matched = 1;  // the file's start is a line's start
  int value = -1;
  bool reading = false, done = false;
  char buf[4096];
  ssize_t got = 0;
  while (!done && (got = ::read(fd, buf, sizeof buf)) > 0)
    for (ssize_t i = 0; i < got && !done; ++i) {
      const char c = buf[i];
      if (reading) {
        if (c >= '0' && c <= '9')
          value = value * 10 + (c - '0');
        else
          done = true;
      } else if (c == kKey[matched]) {
        if (++matched == kKeyLength) reading = true, value = 0;
      } else {
        matched = c == '\n' ? 1 : 0;
      }
    }
  ::close(fd);
  return value > 0 ? value : -1;
}

int free_cores(int cores) {
  if (cores <= 1) return 1;
  std::vector<int> samples;
  for (int k = 0; k < 5; ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const int n = runnable_tasks();
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

bool passive_wait_advised(bool renders_itself) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return false;
  return renders_itself || free_cores_now() < cores_available();
}

void wait_passively_when_cores_are_shared(char** argv, bool renders_itself) {
  if (!passive_wait_advised(renders_itself)) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: then go on as we are
  unsetenv("OMP_WAIT_POLICY");
}

}  // namespace maille
