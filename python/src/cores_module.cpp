// maille._cores: the engine's wait-policy rule (include/maille/cores.hpp) without the engine,
// so that the package (python/maille/__init__.py) can set OMP_WAIT_POLICY before the engine
// loads OpenMP. Built from src/core/free_cores.cpp alone: importing it must not load libgomp.
#include <pybind11/pybind11.h>

#include "maille/cores.hpp"

PYBIND11_MODULE(_cores, m) {
  m.doc() = "The cores free now and the wait policy they call for (include/maille/cores.hpp).";
  m.def(
      "passive_wait_advised", [] { return maille::passive_wait_advised(); },
      "True when the user set no OMP_WAIT_POLICY nor GOMP_SPINCOUNT and another program keeps "
      "a core busy: OpenMP should then wait passively.");
  m.def("free_cores", &maille::free_cores_now,
        "The cores of this process's CPU set that no other program keeps busy now (at least 1).");
  m.def("cores_available", &maille::cores_available, "The size of this process's CPU set.");
}
