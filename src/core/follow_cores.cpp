#include "follow_cores.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "free_cores.hpp"

namespace maille::detail {

namespace {

long this_thread_id() {
#ifdef SYS_gettid
  return long(::syscall(SYS_gettid));
#else
  return 0;  // no thread ids where there are no threads (the WebAssembly build)
#endif
}

// Whether thread `tid` of this process is runnable (state R in /proc/self/task/TID/stat: the
// field after the command name, which ends at the line's last ')').
bool runnable(int tid) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/self/task/%d/stat", tid);
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  char buf[512];
  const ssize_t got = ::read(fd, buf, sizeof buf - 1);
  ::close(fd);
  if (got <= 0) return false;
  buf[got] = '\0';
  const char* end = std::strrchr(buf, ')');
  return end && end[1] == ' ' && end[2] == 'R';
}

}  // namespace

void FreeCoreSampler::find_workers() {
  asker_ = this_thread_id();
  workers_.assign(std::size_t(cores_), 0);
#ifdef _OPENMP
  int* ids = workers_.data();
#pragma omp parallel num_threads(cores_)
  ids[omp_get_thread_num()] = int(this_thread_id());
#endif
  workers_.erase(workers_.begin());  // this thread: counted apart
  std::erase(workers_, 0);
}

int FreeCoreSampler::runnable_workers() const {
  int n = 0;
  for (const int tid : workers_) n += runnable(tid) ? 1 : 0;
  return n;
}

int FreeCoreSampler::operator()() {
  if (this_thread_id() != asker_) find_workers();
  const int all = runnable_tasks();
  if (all < 1) return start_;
  const int others = std::max(all - 1 - runnable_workers(), 0);
  others_[std::size_t(samples_ % kWindow)] = others;
  ++samples_;
  if (samples_ < kWindow) return start_;
  const int fewest = *std::min_element(others_.begin(), others_.end());
  return std::clamp(cores_ - fewest, 1, std::max(cores_, 1));
}

void ThreadChooser::start_trial(std::int64_t now) {
  arm_ = 0;
  threads_ = 1;
  left_ = s_.trial_steps + 1;
  best_ = {INT64_MAX, INT64_MAX};
  last_ = now;
}

int ThreadChooser::before_step(std::int64_t now) {
  // The step that just ended belonged to a trial: its time, unless it was its arm's first.
  if (arm_ >= 0) {
    if (left_ <= s_.trial_steps)
      best_[std::size_t(arm_)] = std::min(best_[std::size_t(arm_)], now - last_);
    last_ = now;
    if (--left_ == 0) {
      if (arm_ == 0) {
        arm_ = 1;
        threads_ = free_;
        left_ = s_.trial_steps + 1;
      } else {
        threads_ = double(best_[1]) <= kGain * double(best_[0]) ? free_ : 1;
        arm_ = -1;
        next_trial_ = now + s_.retrial;
      }
    }
  }
  if (now < next_question_) return threads_;
  next_question_ = now + s_.interval;
  const int free = std::clamp(s_.free_cores(), 1, std::max(s_.cores, 1));
  const bool changed = free != free_;
  free_ = free;
  if (free == 1) {
    arm_ = -1;
    threads_ = 1;
  } else if (s_.trial_steps <= 0) {
    threads_ = free;
  } else if (changed || (arm_ < 0 && now >= next_trial_)) {
    start_trial(now);
  }
  return threads_;
}

}  // namespace maille::detail
