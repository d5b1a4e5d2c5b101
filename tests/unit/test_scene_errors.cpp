// Every scene error path: each file in tests/data/bad/ starts with
//   # expect: LINE:COL KEY | MESSAGE
// and loading it must fail with exactly that location and key ("-" for none) and a message
// containing MESSAGE. The rendered error names the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "maille/scene.hpp"

namespace maille {
namespace {

struct Expectation {
  int line = -1, column = -1;
  std::string key, message;
};

Expectation read_expectation(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string first;
  std::getline(in, first);
  Expectation e;
  const std::string tag = "# expect: ";
  if (first.rfind(tag, 0) != 0) return e;
  std::istringstream s(first.substr(tag.size()));
  char colon;
  std::string bar;
  s >> e.line >> colon >> e.column >> e.key >> bar;
  std::getline(s >> std::ws, e.message);
  if (e.key == "-") e.key.clear();
  return e;
}

std::vector<std::filesystem::path> bad_files() {
  std::vector<std::filesystem::path> out;
  for (const auto& entry : std::filesystem::directory_iterator(MAILLE_TEST_DATA "/bad"))
    if (entry.path().extension() == ".toml") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

class BadScene : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(BadScene, ReportsFileLineColumnAndKey) {
  const auto& file = GetParam();
  const Expectation want = read_expectation(file);
  ASSERT_GE(want.line, 0) << file << " lacks its '# expect:' line";
  const Result<Scene> r = load_scene(file);
  ASSERT_FALSE(r.ok()) << file << " loaded but should not";
  const InputError& e = r.error();
  EXPECT_EQ(e.line, want.line) << e.to_string();
  EXPECT_EQ(e.column, want.column) << e.to_string();
  EXPECT_EQ(e.key, want.key) << e.to_string();
  EXPECT_NE(e.message.find(want.message), std::string::npos) << e.to_string();
  EXPECT_NE(e.to_string().find(file.string()), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Files, BadScene, ::testing::ValuesIn(bad_files()),
                         [](const auto& p) { return p.param.stem().string(); });

TEST(SceneErrors, EveryErrorPathHasAFile) {
  EXPECT_GE(bad_files().size(), 20u);
}

TEST(SceneErrors, MissingFileIsAnError) {
  const Result<Scene> r = load_scene("/nonexistent/scene.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().to_string().find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace maille
