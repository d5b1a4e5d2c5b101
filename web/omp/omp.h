// The OpenMP runtime routines of the threaded WebAssembly build (docs/web.md, "Threads"): the
// engine's sources are compiled with clang's -fopenmp, which turns every `#pragma omp` into
// calls to the LLVM OpenMP runtime's entry points (__kmpc_*); web/omp/kmp_runtime.cpp
// implements those the engine uses on Emscripten's pthreads (Web Workers sharing the module's
// memory). Only the threaded web build puts this directory on the include path.
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

int omp_get_thread_num(void);
int omp_get_num_threads(void);
int omp_get_max_threads(void);
int omp_get_num_procs(void);
int omp_in_parallel(void);
void omp_set_num_threads(int n);
void omp_set_dynamic(int dynamic);
double omp_get_wtime(void);

#ifdef __cplusplus
}
#endif
