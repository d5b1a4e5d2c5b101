// `maille study integrators`: see study.cpp for the files it writes.
#pragma once

#include <filesystem>
#include <string>

namespace maille::app {

struct StudyOptions {
  std::string topic = "integrators";
  std::filesystem::path out = "out/study";
  int threads = 1;     // for the cost table
  bool quick = false;  // two stiffnesses instead of five in the crossover sweep
};
int study(const StudyOptions& o);

}  // namespace maille::app
