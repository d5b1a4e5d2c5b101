// Sweeps: one scene run for every combination of values of some of its keys (`maille sweep`,
// docs/sweep.md). A sweep file:
//
//   scene = "../examples/flag_in_wind.toml"   # relative to the sweep file
//   duration = 2.0                            # simulated seconds per case (default: the scene's)
//   [axes]                                    # key (as for --set) = [values]
//   "flag[0].stiffness" = [100.0, 200.0, 400.0]
//   "simulation.step" = [1e-4, 2e-4]
//   [output]
//   frames = false                            # frames of each case under DIR/cases/<id>/
//
// Every combination of the axes' values is a case. Cases are numbered in the order of the axes'
// product, the axes in the file's order and the last one varying fastest (nested loops), so a
// case's number and id depend on the sweep file only.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "maille/result.hpp"

namespace maille {

struct SweepAxis {
  std::string key;                  // a scene key path, exactly as for --set ("flag[0].stiffness")
  std::vector<std::string> values;  // each as TOML text, as written after `--set KEY=`
  std::vector<std::string> labels;  // each as a summary shows it (the same, strings unquoted)
  int line = 0, column = 0;         // where the key is written in the sweep file (1-based)
};

struct Sweep {
  std::filesystem::path source;    // the sweep file
  std::filesystem::path scene;     // the scene file, resolved against the sweep file's folder
  int scene_line = 0;              // where `scene` is written
  std::optional<double> duration;  // simulated seconds per case, > 0; empty: the scene's
  std::vector<SweepAxis> axes;     // in the file's order, at least one, none empty
  bool frames = false;             // frames of each case under DIR/cases/<id>/

  std::uint64_t case_count() const;  // the product of the axes' sizes
  // Case i, 0 <= i < case_count(): the index of its value on each axis.
  std::vector<std::size_t> coordinates(std::uint64_t i) const;
  // Case i's scene overrides, "KEY=VALUE" (one per axis, in the axes' order), for load_scene.
  std::vector<std::string> overrides(std::uint64_t i) const;
  // Case i's id: its number, zero-padded to the width of the largest (at least 4 digits).
  std::string case_id(std::uint64_t i) const;
};

// A sweep of more cases than this is refused (a typo in an axis, not a plan).
inline constexpr std::uint64_t max_sweep_cases = 1'000'000;

// Reads and checks a sweep file: TOML syntax, known keys of the right types, a scene, at least one
// axis, every axis a non-empty array of values under a key made of key-path characters, at most
// max_sweep_cases cases. Errors carry the file, the line and the key. The scene is not opened.
Result<Sweep> load_sweep(const std::filesystem::path& path);

// Checks the sweep against its scene: the scene loads as it is, and each axis' key is one the
// scene accepts (an override of it with the axis' first value fails, if at all, on its value, not
// on its key: no unknown key, no index beyond the scene's tables). An error is located at the
// sweep file's line for `scene` or for the axis. A bad *value* is not an error here: that case
// fails alone (and is a row of the summary).
std::optional<InputError> check_sweep_keys(const Sweep& sweep);

// Checks every value of every axis against the scene, one override at a time (`maille validate`
// of a sweep file: a case that would fail alone is reported at its axis' line, with the value).
std::optional<InputError> check_sweep_values(const Sweep& sweep);

// Whether a TOML file is a sweep file rather than a scene: its root names a `scene` file (a
// string) or has `[axes]`. False for anything that does not parse.
bool is_sweep_file(const std::filesystem::path& path);

}  // namespace maille
