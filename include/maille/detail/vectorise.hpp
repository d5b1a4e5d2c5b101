// MAILLE_VECTORISE: the loop that follows is to be vectorised whatever the compiler's cost
// model says (the kinds' force laws: packed square roots and divisions over a batch of links).
// It is OpenMP's `simd` directive, which starts no thread and calls no runtime (the web build
// compiles it with -fopenmp-simd alone): the public headers hold no threading construct; the
// parallel loops (work sharing, barriers, atomics) live in the solvers' sources.
#pragma once

#define MAILLE_VECTORISE _Pragma("omp simd")
