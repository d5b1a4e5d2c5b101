// Ctrl-C (SIGINT) and SIGTERM in the command line's programs: one handler for every command.
//
// A command installs it first thing, in one of two modes, and may switch between them:
//   at once   a signal ends the process at once with exit 130, after removing the temporaries
//             of the files being written (AtomicFile: the files already written stay whole) and
//             writing the mode's message to stderr: a scene being loaded (nothing is written yet,
//             and no loop would poll), a study (its loops poll nothing)
//   counted   a signal is counted for the loops to poll (received()); the first one writes the
//             mode's message, if any (`maille sweep`: the second abandons the running cases)
// The Python module installs nothing: Python's own handlers run (maille.run polls them).
#pragma once

#include <atomic>

namespace maille::interrupt {

// Messages must have static storage: the handler writes them (write(2), async-signal-safe).
void at_once(const char* message);
void counted(const char* first_message = nullptr);
// The signals received since the handler was installed: the counter the loops poll.
const std::atomic<int>& received();

}  // namespace maille::interrupt
