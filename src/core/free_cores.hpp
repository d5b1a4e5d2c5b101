// The default thread count follows the cores actually free: on a 2-core machine with
// one core busy elsewhere (another simulation, a browser), two threads made a step 50 to 70
// times slower than one (flag_64: 1,443 to 2,076 ns per particle-step against 28), the barriers
// waiting for a descheduled thread. Private to the core (simulator.cpp).
#pragma once

#include <span>

namespace maille::detail {

// Of `cores` (those this process may run on), how many are free: `cores` less the other
// runnable tasks, taken as the least of `running` (samples of the system's runnable task count,
// this thread included), and at least 1.
int free_cores_from(int cores, std::span<const int> running);

// The tasks runnable now in the whole system, this thread included (/proc/stat's
// procs_running); -1 when it cannot be read. Allocates nothing.
int runnable_tasks();

// The same from /proc/stat's procs_running, sampled 5 times 1 ms apart (a task that was
// runnable in every sample is busy, not passing through); `cores` when it cannot be read.
int free_cores(int cores);

}  // namespace maille::detail
