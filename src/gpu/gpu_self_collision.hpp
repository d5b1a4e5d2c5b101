// The self_collision stage on the GPU (primitive = "points"): a uniform grid rebuilt on the
// device every step by a counting sort, then one gather per particle over the 27 cells around
// its own, adding the CPU stage's contact law (include/maille/detail/link_laws.glsl) into f.
//
//   bounds    the colliding particles' box: a reduction on the device, every step
//   grid      cell size c = max(s, the scene's cell_size) (1 + 2^-10), grown by 1.25 until the
//             box fits the cell budget (max(8 n, 4096) cells, as the CPU's uniform grid)
//   count     per particle: its cell, its rank there (integer atomicAdd on the cell's count)
//   scan      exclusive prefix sums of the counts: Blelloch per block of 512, the blocks'
//             totals scanned the same way one level up (as many levels as needed), added back
//   scatter   each particle to its cell's start + its rank
//   sort      each cell's particles by index: the atomics' order no longer shows in any sum
//   contacts  per particle: candidates of the 27 cells, |d| < s, not excluded (binary search
//             in its row of the exclusion matrix), normal law and friction summed into f
//
// Why these choices (docs/gpu.md, "Self-collision on the GPU", has the measurements):
// - The box is reduced on the device every step: the positions live there, so a host-side box
//   would need a download (a stall every few steps) and a margin guessed against the fastest
//   particle; the reduction is one pass over n, no read-back. Particles outside the grid (not
//   finite) are still clamped to border cells, which only adds candidates.
// - The cell size is the CPU's fixed size or, for "auto", the contact distance s: the CPU's
//   tuner measures CPU times, which say nothing about a GPU; c >= s is what makes 27 cells
//   enough, and the margin 2^-10 absorbs float rounding of the cell coordinates (two particles
//   closer than s can never land two cells apart). Larger cells only add candidates.
// - The exclusion is uploaded as matrix rows whatever the CPU's mode: the matrix and the
//   signature forms remove exactly the same pairs, and rows need no per-cell bookkeeping.
// - Each particle writes only its own force (a gather, as the CPU's response): no float atomics,
//   and with cells sorted by index every step gives the same bits.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gpu_layout.hpp"
#include "gpu_stage.hpp"
#include "kernel.hpp"
#include "maille/gpu.hpp"
#include "maille/model.hpp"
#include "maille/stage.hpp"
#include "non_copyable.hpp"

namespace maille::gpu {

class GpuSelfCollision final : public GpuStage, NonCopyable {
 public:
  // Why the self-collision stage `st`, as configured now, has no GPU version: "" when it runs.
  // Refused: primitive = "triangles", and a broad phase other than uniform (the device builds
  // its own uniform grid: another choice would be silently ignored).
  static std::string check(const Stage& st);

  // The context must be current. `max_invocations`: what one dispatch reaches (caps the cells).
  GpuSelfCollision(const Model& m, const Stage& st, double max_invocations);
  ~GpuSelfCollision() override;

  // Adds the contacts at the device's x and v into f (the step's buffers bound, f written by
  // the forces kernel). Reads the stage's live options (enabled, exclusion) every time.
  void evaluate(double t) override;
  // The grid's buffers after the last evaluate (waits for the device).
  SelfCollisionDebug debug() const;

 private:
  void bind() const;

  const Stage* stage_;
  std::uint32_t particles_ = 0, cells_ = 0;
  float cell_ = 0;
  // The scan's levels: where each level's counts start in sc_cell_start, and how many.
  std::vector<std::uint32_t> level_offset_, level_size_;
  std::array<unsigned, kSelfBufferCount> buffers_{};
  std::vector<Kernel> kernels_;
};

}  // namespace maille::gpu
