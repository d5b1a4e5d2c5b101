// Python's signal handlers for a thread that steps without the GIL (Simulation.step and run,
// maille.run): every 0.1 s, pending() takes the GIL to run them (PyErr_CheckSignals); an
// exception they raise (KeyboardInterrupt) is kept, stops the stepping (a stop request: a long
// implicit step is abandoned, the state of the last whole step stays), and is raised by
// raise_if_pending() once the GIL is back.
#pragma once

#include <Python.h>

#include <chrono>
#include <optional>
#include <thread>

#include <pybind11/pybind11.h>

#include "maille/clock.hpp"

namespace maille::python {

class SignalPoll {
 public:
  // Before releasing the GIL: the first poll is 0.1 s from now.
  void start() { last_ = Clock::now(); }

  // On the stepping thread, without the GIL.
  bool pending() {
    if (raised_) return true;
    const auto now = Clock::now();
    if (now - last_ < std::chrono::milliseconds(100)) return false;
    last_ = now;
    if (_Py_IsFinalizing()) park();
    PyGILState_STATE gil = PyGILState_Ensure();
    if (PyErr_CheckSignals() != 0) {
      Raised r;
      PyErr_Fetch(&r.type, &r.value, &r.traceback);
      raised_ = r;
    }
    PyGILState_Release(gil);
    return raised_.has_value();
  }

  // With the GIL: raises what a signal handler raised during the stepping, if anything.
  void raise_if_pending() {
    if (!raised_) return;
    PyErr_Restore(raised_->type, raised_->value, raised_->traceback);
    raised_.reset();
    throw pybind11::error_already_set();
  }

  // A thread that must not come back into an interpreter that is shutting down waits here
  // until the process ends (a daemon thread: the interpreter does not wait for it).
  [[noreturn]] static void park() {
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
  }

 private:
  using Clock = WallClock;
  struct Raised {
    PyObject *type = nullptr, *value = nullptr, *traceback = nullptr;
  };
  Clock::time_point last_;
  std::optional<Raised> raised_;
};

}  // namespace maille::python
