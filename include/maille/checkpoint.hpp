// Checkpoints: the whole State (positions, velocities, forces, time, step, the scheme's history,
// the stages' memory) plus what an app needs to continue its files (frames published, stats rows
// written), tied to the model it belongs to by a fingerprint. Resuming from one continues
// bit-identically: N steps + resume + N steps equals 2N steps in one go, for every scheme.
//
// Format (binary, this machine's byte order; version 2): "MAILLECK", u32 version, u32
// sizeof(Real), u64 model fingerprint, the scheme's name, f64 step, u64 frames, u64 stats rows,
// then the State (u64 points, f64 time, u64 step, history, stage memory, x, v, f as raw Reals),
// then a u64 checksum of every byte before it: a file changed anywhere (one flipped byte in the
// frame counter or the scheme's history) is refused as corrupt, never resumed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "maille/model.hpp"
#include "maille/result.hpp"
#include "maille/simulator.hpp"
#include "maille/state.hpp"

namespace maille {

struct Checkpoint {
  State state;
  std::string integrator;  // the scheme that wrote it
  double step = 0;         // h, s
  std::uint64_t frames_published = 0;
  std::uint64_t stats_rows = 0;  // rows of stats.csv written when it was taken
  std::uint64_t model_fingerprint = 0;
};

// A hash of everything in the model that a state depends on: points (kind, mass, initial
// position and velocity), links (kind, ends, parameters), faces, groups, every field (the wind's
// density, drag and gusts included), drives (path and parameters), geometric points, stages
// (name, variant, StageSpec::fingerprint) and Model::scene_digest, the scene's every key after
// --set overrides but those that only choose outputs (scene_digest.hpp): a key added to the
// scene format is covered without being listed here.
std::uint64_t model_fingerprint(const Model& m);
// The model's fingerprint and the settings that change a trajectory besides the scheme and the
// step (which a resume checks on their own, with a message saying both values): the implicit
// solver's settings, the backend, and which of the model's stages run (--no-self-collision).
// What apps write into checkpoints and compare on resume.
std::uint64_t model_fingerprint(const Model& m, const SimulationSettings& s);

// Written whole or not at all (temporary file, renamed). Throws std::runtime_error naming the
// path and the cause.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c);
// Errors name the file: unreadable, not a checkpoint, another version or precision, truncated,
// corrupt (checksum mismatch), or written for another model (fingerprint mismatch: compared with
// model_fingerprint(model), or with `fingerprint` given by the caller).
Result<Checkpoint> read_checkpoint(const std::filesystem::path& path, const Model& model);
Result<Checkpoint> read_checkpoint(const std::filesystem::path& path, std::uint64_t fingerprint);

// "the checkpoint was taken with S at h = H s; <now> S' at h = H' s", both steps at 17 digits
// (%.17g) so that values a rounding of 6 digits would show equal read differently.
std::string scheme_mismatch(const std::string& integrator, double step, const std::string& now,
                            const std::string& now_integrator, double now_step);

}  // namespace maille
