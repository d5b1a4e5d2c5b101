// Thread counts the engine can trust to start (OpenMP through libgomp).
//
// Two ways libgomp ends a program that asked for threads, which the engine turns into answers:
// - Its threads do not survive fork(). A child forked after the engine ran teams of several
//   threads (Python's multiprocessing with the "fork" start method) that asks for a team again
//   waits for ever at the first barrier, for threads that exist only in the parent. In such a
//   child usable_threads() is 1: the engine runs on the calling thread, which needs no team.
// - It exits the process when it cannot create a thread (a memory limit such as ulimit -v
//   with 8 MiB stacks, ulimit -u). threads_startable() tries first and says why not.
#pragma once

#include <string>

namespace maille {

// `requested`, or 1 in a child forked after the engine ran teams of several threads.
int usable_threads(int requested);
// Whether this process is such a child.
bool forked_after_teams();
// The engine is about to run teams of `threads` threads (a fork after this is remembered).
void note_teams(int threads);
// "" when `threads` threads (the caller and threads - 1 more, with OpenMP's stack size) can run
// at once now; else why not ("cannot start 1024 threads: Resource temporarily unavailable").
std::string threads_startable(int threads);

}  // namespace maille
