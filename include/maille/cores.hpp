// The cores this process may run on that no other program keeps busy now (threads
// that never make a run slower). The simulator's default thread count follows it; apps use it
// to choose OpenMP's wait policy before they start.
#pragma once

namespace maille {

// The cores of this process's CPU set less the other tasks runnable in every one of 5 samples
// of /proc/stat (1 ms apart), at least 1; the CPU set's size when /proc cannot be read.
int free_cores_now();
// The size of this process's CPU set (sched_getaffinity), at least 1.
int cores_available();

// Whether a program about to load OpenMP should wait passively: the user set no OMP_WAIT_POLICY
// nor GOMP_SPINCOUNT, and the cores are shared (another program keeps one busy, or
// `renders_itself`). The rule of wait_passively_when_cores_are_shared below; the Python package
// asks it before it loads the engine (python/maille/__init__.py).
bool passive_wait_advised(bool renders_itself = false);

// OpenMP (libgomp) reads its wait policy when the program loads, before main. Unset, a thread
// waiting at a barrier spins for a long while, which is right on free cores and ruinous when
// another thread holds one: its partner is descheduled and the spin burns the time it needs
// (flag_64 on 2 threads beside a busy core: 1660-2655 ns per particle-step spinning, 52 passive;
// docs/benchmarks.md). Called first thing in main: when cores are shared (another program keeps
// one busy, or `renders_itself`: the program's own render loop holds a core, as the viewer's
// does), the program starts again (execv of /proc/self/exe, same arguments, same PID) with
// OMP_WAIT_POLICY=passive. A policy the user set, or a GOMP_SPINCOUNT, is kept; when the restart
// fails, the program goes on as it is.
void wait_passively_when_cores_are_shared(char** argv, bool renders_itself = false);

}  // namespace maille
