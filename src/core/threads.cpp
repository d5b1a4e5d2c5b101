#include "maille/threads.hpp"

#include <pthread.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace maille {

namespace {

std::atomic<bool> g_teams{false};   // this process has run teams of several threads
std::atomic<bool> g_forked{false};  // and this is a child forked after that

extern "C" void on_fork_child() {
  if (g_teams.load(std::memory_order_relaxed)) g_forked.store(true, std::memory_order_relaxed);
}

// The stack size libgomp gives its threads: OMP_STACKSIZE / GOMP_STACKSIZE (a number with an
// optional B, K, M or G suffix, kilobytes by default), else the default of new threads.
std::size_t openmp_stack_bytes() {
  for (const char* name : {"OMP_STACKSIZE", "GOMP_STACKSIZE"}) {
    const char* text = std::getenv(name);
    if (!text || !*text) continue;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text, &end, 10);
    if (end == text) continue;
    const char unit = *end ? *end : 'K';
    const unsigned long long scale = unit == 'B' || unit == 'b'   ? 1ull
                                     : unit == 'M' || unit == 'm' ? 1ull << 20
                                     : unit == 'G' || unit == 'g' ? 1ull << 30
                                                                  : 1ull << 10;
    return std::size_t(v * scale);
  }
  return 0;
}

// Threads that wait until every probe has started, so that they exist at the same time.
struct Gate {
  std::mutex m;
};

extern "C" void* wait_at_gate(void* arg) {
  auto* gate = static_cast<Gate*>(arg);
  const std::lock_guard<std::mutex> lock(gate->m);  // blocks until the creator opens it
  return nullptr;
}

}  // namespace

int usable_threads(int requested) {
  return requested > 1 && g_forked.load(std::memory_order_relaxed) ? 1 : requested;
}

bool forked_after_teams() {
  return g_forked.load(std::memory_order_relaxed);
}

void note_teams(int threads) {
  if (threads <= 1 || g_teams.load(std::memory_order_relaxed)) return;
  static std::once_flag registered;
  std::call_once(registered, [] { pthread_atfork(nullptr, nullptr, on_fork_child); });
  g_teams.store(true, std::memory_order_relaxed);
}

std::string threads_startable(int threads) {
  if (threads <= 1 || forked_after_teams()) return {};
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  if (const std::size_t stack = openmp_stack_bytes(); stack > 0)
    pthread_attr_setstacksize(&attr, stack);
  Gate gate;
  std::vector<pthread_t> started;
  int error = 0;
  {
    const std::lock_guard<std::mutex> lock(gate.m);
    for (int i = 1; i < threads && error == 0; ++i) {
      pthread_t t;
      error = pthread_create(&t, &attr, wait_at_gate, &gate);
      if (error == 0) started.push_back(t);
    }
  }
  for (const pthread_t t : started) pthread_join(t, nullptr);
  pthread_attr_destroy(&attr);
  if (error == 0) return {};
  return "cannot start " + std::to_string(threads) + " threads (" + std::strerror(error) + "; " +
         std::to_string(started.size() + 1) +
         " could run at once): use fewer threads, or raise the limit that stopped them (ulimit -v, "
         "ulimit -u)";
}

}  // namespace maille
