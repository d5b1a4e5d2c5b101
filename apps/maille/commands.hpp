// The subcommands of `maille`. Exit codes: 0 success, 1 bad input, 2 usage, 3 blow-up,
// 4 output error, 130 interrupted (Ctrl-C).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace maille::app {

enum Exit : int {
  ok = 0,
  bad_input = 1,
  usage = 2,
  blow_up = 3,
  output_error = 4,
  interrupted = 130
};

struct RunOptions {
  std::string scene;
  std::optional<std::uint64_t> steps;
  std::optional<double> duration;
  std::string out;  // empty: out/<scene name>
  std::optional<int> every;
  std::string format = "ply";
  std::optional<int> threads;
  bool no_frames = false;
};
int run(const RunOptions& o);
int validate(const std::string& scene);
int info(const std::string& scene);

struct BenchOptions {
  std::string scene;
  std::uint64_t steps = 1000;
  std::optional<int> threads;
  int repeat = 3;
  bool header = true;
};
int bench(const BenchOptions& o);

}  // namespace maille::app
