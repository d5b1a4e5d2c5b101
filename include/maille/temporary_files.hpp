// The temporaries of AtomicFile (io.hpp) that are open right now, for a signal handler: an app
// that must stop at once (Ctrl-C while a scene loads, or during a study, whose loops do not
// poll a flag) removes them and exits, leaving no NAME.tmp behind.
#pragma once

namespace maille {

// Unlinks every temporary an AtomicFile has open. Async-signal-safe (unlink and atomics only):
// call it from a signal handler, then _exit.
void remove_open_temporaries() noexcept;

}  // namespace maille
