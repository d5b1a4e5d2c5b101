// `maille study integrators | self-collision | validity | obstacles`: see study.cpp and
// study_*.cpp for the files they write.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace maille::app {

struct StudyOptions {
  std::string topic = "integrators";
  std::filesystem::path out = "out/study";
  int threads = 1;     // for the cost table
  bool quick = false;  // two stiffnesses instead of five in the crossover sweep
};
int study(const StudyOptions& o);

// Writes one CSV file of the study (whole or not at all).
using StudyWriter = std::function<void(const char*, const std::function<void(std::ostream&)>&)>;
void study_self_collision(const StudyOptions& o, const StudyWriter& write);
void study_validity(const StudyOptions& o, const StudyWriter& write);
void study_obstacles(const StudyOptions& o, const StudyWriter& write);

}  // namespace maille::app
