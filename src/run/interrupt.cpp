#include "maille/interrupt.hpp"

#include <unistd.h>

#include <csignal>

#include "maille/exit_codes.hpp"
#include "maille/temporary_files.hpp"

namespace maille::interrupt {

namespace {

std::atomic<int> g_received{0};
std::atomic<bool> g_at_once{false};
std::atomic<const char*> g_message{nullptr};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free &&
              std::atomic<const char*>::is_always_lock_free);

void say(const char* m) {  // write(2) and a hand-counted length: async-signal-safe
  if (!m) return;
  std::size_t n = 0;
  while (m[n]) ++n;
  [[maybe_unused]] const auto w = ::write(STDERR_FILENO, m, n);
}

extern "C" void on_signal(int) {
  const int before = g_received.fetch_add(1);
  if (g_at_once) {
    remove_open_temporaries();
    say(g_message);
    ::_exit(exit_code::interrupted);
  }
  if (before == 0) say(g_message);
}

void install() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

}  // namespace

void at_once(const char* message) {
  g_message = message;
  g_at_once = true;
  install();
}

void counted(const char* first_message) {
  g_message = first_message;
  g_at_once = false;
  install();
}

const std::atomic<int>& received() {
  return g_received;
}

}  // namespace maille::interrupt
