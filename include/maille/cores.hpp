// The cores this process may run on that no other program keeps busy now (issue 24: threads
// that never make a run slower). The simulator's default thread count follows it; apps use it
// to choose OpenMP's wait policy before they start.
#pragma once

namespace maille {

// The cores of this process's CPU set less the other tasks runnable in every one of 5 samples
// of /proc/stat (1 ms apart), at least 1; the CPU set's size when /proc cannot be read.
int free_cores_now();
// The size of this process's CPU set (sched_getaffinity), at least 1.
int cores_available();

}  // namespace maille
