// `maille sweep SWEEP.toml --out DIR [--threads N]`: every case of a sweep file
// (include/maille/sweep.hpp), under mpirun / srun across ranks (sweep_world.hpp), into
// DIR/cases/<id>/ and DIR/summary.csv. docs/sweep.md describes the files, resuming and Ctrl-C.
#pragma once

#include <optional>
#include <string>

namespace maille::app {

struct SweepOptions {
  std::string sweep;           // the sweep file
  std::string out;             // DIR
  std::optional<int> threads;  // threads of each case, as `maille run --threads`
};

// Exit codes: 0 every case has its row (whatever its status), 1 a bad sweep file (or DIR holds
// another sweep's cases, or another sweep runs there), 2 usage, 4 an output error (DIR, the
// summary, or a case's files), 130 interrupted (the summary lists the cases done).
int sweep(const SweepOptions& o);

}  // namespace maille::app
