// How a run of a scene ends, as the command line's exit status: `maille run` exits with it, a
// sweep records it per case (summary.csv's exit_code), the Python module's run() raises by it.
#pragma once

namespace maille::exit_code {

enum Exit : int {
  ok = 0,
  bad_input = 1,     // the scene, an override or a value refused
  usage = 2,         // the command's options (a run longer than limits::max_steps)
  blow_up = 3,       // a numerical blow-up (the files written up to it are complete)
  output_error = 4,  // a file or folder could not be written (the cause is named)
  interrupted = 130  // Ctrl-C or SIGTERM (the files written so far are complete)
};

}  // namespace maille::exit_code
