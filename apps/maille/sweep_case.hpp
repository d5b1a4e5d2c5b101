// One case of a sweep (`maille sweep`, docs/sweep.md): the scene with the case's overrides, run
// as `maille run SCENE --set ... --duration D --no-frames` runs it (frames with [output] frames),
// into DIR/cases/<id>/, and its result: the summary's row, also written to DIR/cases/<id>/done
// once the case's files are complete (the marker a rerun skips the case by).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "maille/sweep.hpp"

namespace maille::app {

struct CaseResult {
  std::uint64_t index = 0;  // the case's number in the sweep
  std::string status;       // ok | blowup | error
  int exit_code = 0;        // what `maille run` would exit with: 0, 1 bad value, 2, 3 blow-up, 4
  std::string message;      // the error or the blow-up's report; empty when ok
  int rank = 0;             // the MPI rank that ran it
  double wall_seconds = 0;
  double simulated_seconds = 0;
  std::optional<double> final_energy;  // J, total; only when ok
  std::string stats_header;            // the first line of its stats.csv (empty: none written)
  std::string stats_last;              // the last line of its stats.csv (empty: no row)
  // Not a result to keep: interrupted (a second Ctrl-C), or its files could not be written (an
  // output error, exit_code 4): no marker is written and a rerun runs it again.
  bool retry = false;

  // One record per line, key=value, newlines escaped: the marker's text and the MPI message.
  std::string serialize() const;
  static std::optional<CaseResult> parse(const std::string& text);
};

// Runs case `index` into `dir` (removed first: a case never mixes files of two runs), then writes
// dir/done (atomically, after everything else) unless the result is one to retry. `threads`: as
// `maille run --threads`. `stop` >= 2 abandons the case between two steps (a second Ctrl-C).
CaseResult run_case(const Sweep& sweep, std::uint64_t index, const std::filesystem::path& dir,
                    std::optional<int> threads, int rank, const std::atomic<int>& stop);

// The result recorded in dir/done by an earlier run, if any and if it is case `index`'s.
std::optional<CaseResult> read_marker(const std::filesystem::path& dir, std::uint64_t index);

}  // namespace maille::app
