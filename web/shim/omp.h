// The OpenMP runtime as a program built without OpenMP sees it (the OpenMP specification's stub
// routines): one thread, thread 0. The WebAssembly build runs the engine on one thread; its
// `#pragma omp` lines are ignored (no -fopenmp), and the few runtime calls the engine makes
// (thread ids for per-thread buffers, the core count) come from here. Only the web build puts
// this directory on the include path.
#pragma once

inline int omp_get_thread_num() { return 0; }
inline int omp_get_num_threads() { return 1; }
inline int omp_get_max_threads() { return 1; }
inline int omp_get_num_procs() { return 1; }
inline int omp_in_parallel() { return 0; }
inline void omp_set_num_threads(int) {}
inline void omp_set_dynamic(int) {}
