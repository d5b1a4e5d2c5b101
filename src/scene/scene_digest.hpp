// The scene digest (Model::scene_digest): a hash of the parsed scene after --set overrides,
// key by key in sorted order, values by type and exact bits, leaving out the keys that only
// choose outputs. Checkpoints compare it, so an edited scene is refused whatever key changed,
// including keys added to the format later (nothing here lists the keys that count).
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#define TOML_HEADER_ONLY 0
#include <toml++/toml.h>

namespace maille {

// Keys left out, because they change what is written, shown or checked but never a state:
//   [scene] (name, description: the output folder), [audio] and [[listen]] (what is recorded),
//   [simulation] duration, output_every, sample_every, threads (results are bit-identical on
//   any thread count), runaway_factor, gpu_device (which device of the backend), and
//   [simulation] integrator and step, which a resume compares on its own with both values in
//   the message.
std::uint64_t scene_digest(const toml::table& root);

// The tables that choose outputs only (left out of the digest; a [[control]] cannot play them).
inline constexpr std::array<std::string_view, 4> kOutputTables{"scene", "audio", "listen",
                                                               "control"};

}  // namespace maille
