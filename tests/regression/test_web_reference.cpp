// The native hashes the browser test compares the WebAssembly build with
// (web/tests/reference_hashes.txt, read by web/tests/browser_test.mjs): each line names an
// example and a step count, and gives the state hash of that run on one thread on the CPU, as the
// golden tests make it (tests/regression/test_golden.cpp). Checked here so that the file follows
// the engine: a change of trajectory fails here by name, and is recorded with
//
//   MAILLE_UPDATE_GOLDEN=1 ctest --test-dir build/dev -R web_reference
//
// (the golden hashes of the examples themselves, which the browser test also compares, are
// tests/golden/NAME.hash).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "maille/audio.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

struct Reference {
  std::string id, example;
  std::uint64_t steps = 0;
  std::string hash;
};

const char* const kFile = MAILLE_SOURCE_DIR "/web/tests/reference_hashes.txt";

std::vector<std::string> lines() {
  std::ifstream in(kFile);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string hex(std::uint64_t h) {
  char s[17];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
  return s;
}

TEST(WebReference, native_hashes_of_the_browser_test) {
  std::vector<std::string> text = lines();
  ASSERT_FALSE(text.empty()) << "cannot read " << kFile;
  const char* update = std::getenv("MAILLE_UPDATE_GOLDEN");
  const bool record = update && *update == '1';
  for (std::string& line : text) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Reference r;
    fields >> r.id >> r.example >> r.steps >> r.hash;
    ASSERT_FALSE(r.example.empty() || r.steps == 0) << kFile << ": malformed line '" << line << "'";
    auto scene = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + r.example + ".toml");
    ASSERT_TRUE(scene.ok()) << scene.error().to_string();
    scene->settings.backend = "cpu";
    scene->settings.threads = 1;
    Simulator sim(std::move(scene->model), scene->settings);
    ASSERT_TRUE(sim.run_steps(r.steps)) << sim.blow_up()->message;
    const std::string hash = hex(state_hash(sim.state()));
    if (record) {
      line = r.id + " " + r.example + " " + std::to_string(r.steps) + " " + hash;
    } else {
      EXPECT_EQ(hash, r.hash)
          << r.id << ": the native run changed; record the new hash with "
          << "MAILLE_UPDATE_GOLDEN=1 ctest --test-dir build/dev -R web_reference";
    }
  }
  if (record) {
    std::ofstream out(kFile);
    for (const std::string& line : text) out << line << '\n';
    GTEST_SKIP() << "recorded " << kFile;
  }
}

// The sound the page makes (web/src/playground_sound.cpp) against the Recorder that
// `maille run --audio` writes from (web/tests/reference_audio.txt): each line runs an example
// with --set overrides for STEPS steps and gives FNV-1a 64 of the first SAMPLES frames of its
// channels (float32 little-endian, channel-interleaved, before any gain: a float32 WAV written
// with audio.gain = 1 holds these very values). The browser test computes the same hash of the
// page's samples.
const char* const kAudioFile = MAILLE_SOURCE_DIR "/web/tests/reference_audio.txt";

std::uint64_t fnv1a(const std::vector<std::vector<float>>& channels, std::size_t frames) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64 offset basis
  for (std::size_t k = 0; k < frames; ++k)
    for (const auto& c : channels) {
      unsigned char b[4];
      std::memcpy(b, &c[k], 4);
      for (const unsigned char x : b) h = (h ^ x) * 1099511628211ull;
    }
  return h;
}

TEST(WebReference, native_sound_of_the_browser_test) {
  std::ifstream in(kAudioFile);
  std::vector<std::string> text;
  for (std::string line; std::getline(in, line);) text.push_back(line);
  ASSERT_FALSE(text.empty()) << "cannot read " << kAudioFile;
  const char* update = std::getenv("MAILLE_UPDATE_GOLDEN");
  const bool record = update && *update == '1';
  for (std::string& line : text) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string id, example, hash;
    std::uint64_t steps = 0;
    std::size_t frames = 0;
    fields >> id >> example >> steps >> frames >> hash;
    std::vector<std::string> overrides;
    for (std::string o; fields >> o;) overrides.push_back(o);
    ASSERT_FALSE(example.empty() || steps == 0 || frames == 0)
        << kAudioFile << ": malformed line '" << line << "'";
    auto scene =
        load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + example + ".toml", overrides);
    ASSERT_TRUE(scene.ok()) << scene.error().to_string();
    scene->settings.backend = "cpu";
    scene->settings.threads = 1;
    audio::Recorder recorder(scene->audio, scene->settings.step);
    Simulator sim(std::move(scene->model), scene->settings);
    recorder.attach(sim);
    ASSERT_TRUE(sim.run_steps(steps)) << sim.blow_up()->message;
    recorder.finish();
    for (const auto& c : recorder.channels()) ASSERT_GE(c.size(), frames) << id;
    const std::string got = hex(fnv1a(recorder.channels(), frames));
    if (record) {
      line = id + " " + example + " " + std::to_string(steps) + " " + std::to_string(frames) + " " +
             got;
      for (const std::string& o : overrides) line += " " + o;
    } else {
      EXPECT_EQ(got, hash) << id << ": the native sound changed; record it with "
                           << "MAILLE_UPDATE_GOLDEN=1 ctest --test-dir build/dev -R web_reference";
    }
  }
  if (record) {
    std::ofstream out(kAudioFile);
    for (const std::string& line : text) out << line << '\n';
    GTEST_SKIP() << "recorded " << kAudioFile;
  }
}

}  // namespace
}  // namespace maille
