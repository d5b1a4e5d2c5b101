// Scenes: TOML text -> validated model and settings. docs/scene-format.md lists every key.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "maille/audio.hpp"
#include "maille/link_registry.hpp"
#include "maille/model.hpp"
#include "maille/result.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"

namespace maille {

struct Scene {
  std::string name;  // [scene] name, or the file stem
  std::string description;
  std::filesystem::path source;
  Model model;
  SimulationSettings settings;
  audio::AudioSpec audio;  // [[listen]] and [audio] (docs/sound.md); no listener: silent
};

// Reads and validates a scene. Link kinds are looked up in `kinds` and stage tables in `stages`
// (the built-ins by default; pass registries with your own entries added to use them in scene
// files).
Result<Scene> load_scene(const std::filesystem::path& path);
Result<Scene> load_scene(const std::filesystem::path& path, const LinkKindRegistry& kinds);
Result<Scene> load_scene(const std::filesystem::path& path, const LinkKindRegistry& kinds,
                         const StageRegistry& stages);
// With command-line overrides applied first (`--set KEY=VALUE`, see src/scene/overrides.hpp):
// the same validation, and errors in an override name it.
Result<Scene> load_scene(const std::filesystem::path& path, std::span<const std::string> overrides);
Result<Scene> load_scene(const std::filesystem::path& path, const LinkKindRegistry& kinds,
                         const StageRegistry& stages, std::span<const std::string> overrides);
// Same, from text; `source_name` is used in error messages.
Result<Scene> parse_scene(std::string_view text, const std::string& source_name,
                          const LinkKindRegistry& kinds);
Result<Scene> parse_scene(std::string_view text, const std::string& source_name,
                          const LinkKindRegistry& kinds, const StageRegistry& stages,
                          std::span<const std::string> overrides = {});

namespace audio {
struct ParameterTable;  // live.hpp
}
// A parameter [[control]] made playable (`maille play`, src/scene/control_keys.cpp): the scene
// at `path` (with `overrides`) read again with the control's key at values across its range,
// each through the reader's validation; refused, with the control's line and column, when the
// key changes the model's structure or nothing it holds, or when an end of the range needs a
// smaller step than settings.step. `playing`: the model as read (before a simulator has it).
Result<audio::ParameterTable> build_parameter_table(const std::filesystem::path& path,
                                                    std::span<const std::string> overrides,
                                                    const Model& playing,
                                                    const SimulationSettings& settings,
                                                    const audio::Control& control);

}  // namespace maille
