// Checkpoints: the whole State (positions, velocities, forces, time, step, the scheme's history,
// the stages' memory) plus what an app needs to continue its files (frames published, stats rows
// written), tied to the model it belongs to by a fingerprint. Resuming from one continues
// bit-identically: N steps + resume + N steps equals 2N steps in one go, for every scheme.
//
// Format (binary, this machine's byte order; version 1): "MAILLECK", u32 version, u32
// sizeof(Real), u64 model fingerprint, the scheme's name, f64 step, u64 frames, u64 stats rows,
// then the State (u64 points, f64 time, u64 step, history, stage memory, x, v, f as raw Reals).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "maille/model.hpp"
#include "maille/result.hpp"
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
// position and velocity), links (kind, ends, parameters), faces, fields, drives' count, stages.
std::uint64_t model_fingerprint(const Model& m);

// Written whole or not at all (temporary file, renamed). Throws std::runtime_error naming the
// path and the cause.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c);
// Errors name the file: unreadable, not a checkpoint, another version or precision, truncated,
// or written for another model (fingerprint mismatch).
Result<Checkpoint> read_checkpoint(const std::filesystem::path& path, const Model& model);

}  // namespace maille
