# The WebAssembly build's dependencies, included by the top-level CMakeLists.txt under Emscripten
# (scripts/web.sh configures it with emcmake). The engine's libraries (src/CMakeLists.txt) are
# compiled from the same source lists as natively; what the browser lacks is replaced here:
#   OpenMP     none: one thread. An empty OpenMP::OpenMP_CXX whose include directory holds the
#              OpenMP specification's stub routines (web/shim/omp.h); `#pragma omp` is ignored.
#   toml++     from Debian's headers alone (its CMake and pkg-config files force the compiled
#              library): src/scene/toml_cursor.cpp compiles its implementation, as natively.
#   Eigen      its headers, as a system directory.
#   libc++ 13  lacks floating-point to_chars / from_chars and bit_cast: web/shim/std_compat.hpp,
#              force-included, adds them (the native build never sees it).
# Never the host's /usr/include itself: only a directory holding a link to toml++'s headers.
set(MAILLE_BUILD_RENDER OFF CACHE BOOL "" FORCE)
set(MAILLE_BUILD_PYTHON OFF CACHE BOOL "" FORCE)
set(MAILLE_BUILD_TESTS OFF CACHE BOOL "" FORCE)
set(MAILLE_BUILD_BENCH OFF CACHE BOOL "" FORCE)
set(MAILLE_ARCH "portable" CACHE STRING "" FORCE)  # no -march: -msimd128 below

set(MAILLE_TOMLPP_HEADERS "/usr/include/toml++" CACHE PATH "toml++'s headers (toml.h)")
set(MAILLE_EIGEN_HEADERS "/usr/include/eigen3" CACHE PATH "Eigen's headers (Eigen/Core)")
foreach(header ${MAILLE_TOMLPP_HEADERS}/toml.h ${MAILLE_EIGEN_HEADERS}/Eigen/Core)
  if(NOT EXISTS ${header})
    message(FATAL_ERROR "maille (web): ${header} not found; scripts/setup.sh installs it")
  endif()
endforeach()
set(host_headers ${CMAKE_BINARY_DIR}/host_headers)
file(MAKE_DIRECTORY ${host_headers})
file(CREATE_LINK ${MAILLE_TOMLPP_HEADERS} ${host_headers}/toml++ SYMBOLIC)

# Two builds of the module (docs/web.md, "Threads"):
#   MAILLE_WEB_THREADS=OFF  maille.js: one thread. -fopenmp-simd: the engine's `#pragma omp simd`
#                           loops (the link pools' kernels) are vectorised as natively, with no
#                           runtime and without _OPENMP; the other `#pragma omp` lines are
#                           ignored, and web/shim/omp.h answers the runtime calls (thread 0 of 1).
#   MAILLE_WEB_THREADS=ON   maille-mt.js: -fopenmp and -pthread: the engine's OpenMP code as
#                           natively, on Web Workers through the small runtime web/omp/ (clang's
#                           __kmpc_* entry points on Emscripten's pthreads). Needs a
#                           cross-origin isolated page (SharedArrayBuffer).
option(MAILLE_WEB_THREADS "the threaded module (OpenMP on Web Workers), maille-mt.js" OFF)
add_library(OpenMP::OpenMP_CXX INTERFACE IMPORTED)
if(MAILLE_WEB_THREADS)
  set_target_properties(OpenMP::OpenMP_CXX PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/web/omp
    INTERFACE_COMPILE_OPTIONS "-fopenmp")
  add_compile_options(-pthread)
  add_link_options(-pthread)
else()
  set_target_properties(OpenMP::OpenMP_CXX PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/web/shim
    INTERFACE_COMPILE_OPTIONS "-fopenmp-simd;-Wno-unknown-pragmas;-Wno-source-uses-openmp")
endif()
add_library(tomlplusplus::tomlplusplus INTERFACE IMPORTED)
set_target_properties(tomlplusplus::tomlplusplus PROPERTIES
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES ${host_headers}
  INTERFACE_INCLUDE_DIRECTORIES ${host_headers})
add_library(Eigen3::Eigen INTERFACE IMPORTED)
set_target_properties(Eigen3::Eigen PROPERTIES
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES ${MAILLE_EIGEN_HEADERS}
  INTERFACE_INCLUDE_DIRECTORIES ${MAILLE_EIGEN_HEADERS})

# WebAssembly SIMD (128-bit vectors: what -march gives natively), C++ exceptions (scene errors
# are exceptions inside the reader), and the C++20 library pieces libc++ 13 lacks
# (web/shim/std_compat.hpp: floating-point to_chars / from_chars, bit_cast).
# Exceptions: WebAssembly's own (-fwasm-exceptions: no cost until one is thrown; Chromium 95,
# Firefox 100, Safari 15.2) or Emscripten's emulation in JavaScript (-fexceptions: every call
# that may throw from a frame with something to unwind goes through JavaScript).
# The threaded module always takes Emscripten's: with -pthread, Debian's Emscripten 3.1.6 does not
# catch a WebAssembly exception (a six-line throw and catch aborts with an uncaught
# WebAssembly.Exception; the same program without -pthread, or with -fexceptions, catches it).
option(MAILLE_WASM_EXCEPTIONS "WebAssembly exceptions (-fwasm-exceptions) instead of -fexceptions" ON)
if(MAILLE_WASM_EXCEPTIONS AND NOT MAILLE_WEB_THREADS)
  set(maille_eh -fwasm-exceptions)
else()
  set(maille_eh -fexceptions)
endif()
add_compile_options(-msimd128 ${maille_eh}
  "SHELL:-include ${PROJECT_SOURCE_DIR}/web/shim/std_compat.hpp")
add_link_options(${maille_eh})
