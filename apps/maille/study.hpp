// `maille study integrators | self-collision | validity | obstacles | large-steps | all`: see
// study.cpp and study_*.cpp for the files they write (`all`: each study into OUT/<study>/).
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace maille {
class Simulator;
}

namespace maille::app {

struct StudyOptions {
  std::string topic = "integrators";
  std::filesystem::path out = "out/study";
  int threads = 1;     // for the cost table
  bool quick = false;  // shorter sweeps and runs in every study (for CI)
  // Where the studies read the examples they run (large-steps: cloth_on_sphere.toml); main.cpp
  // defaults it to the source tree's examples/.
  std::filesystem::path examples;
};
int study(const StudyOptions& o);

// Writes one CSV file of the study (whole or not at all).
using StudyWriter = std::function<void(const char*, const std::function<void(std::ostream&)>&)>;
void study_self_collision(const StudyOptions& o, const StudyWriter& write);
void study_validity(const StudyOptions& o, const StudyWriter& write);
void study_obstacles(const StudyOptions& o, const StudyWriter& write);
void study_large_steps(const StudyOptions& o, const StudyWriter& write);

// The largest stretch of the structural links of a cloth of grid spacing `spacing` (study.cpp).
double structural_stretch(const Simulator& sim, double spacing);

}  // namespace maille::app
