// Mutable simulation state: what changes every step. The model (model.hpp) never does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "maille/vec3.hpp"

namespace maille {

// Point arrays (x, v, f) live in one allocation, each starting at a different offset modulo
// 4 KiB: with power-of-two grid sizes, arrays that start on the same 4 KiB boundary alias in the
// L1 cache and store-to-load forwarding (measured 3x slower at 2048^2 without the stagger).
class PointArrays {
 public:
  PointArrays() = default;
  PointArrays(std::size_t count, int arrays);
  PointArrays(const PointArrays& other);
  PointArrays& operator=(const PointArrays& other);
  PointArrays(PointArrays&&) noexcept = default;
  PointArrays& operator=(PointArrays&&) noexcept = default;

  std::span<Vec3> array(int which) { return {base(which), count_}; }
  std::span<const Vec3> array(int which) const { return {base(which), count_}; }
  std::size_t count() const { return count_; }

 private:
  Vec3* base(int which) const;
  std::size_t count_ = 0;
  int arrays_ = 0;
  std::size_t stride_bytes_ = 0;
  std::unique_ptr<std::byte[]> storage_;
};

// What a scheme carries from one step to the next. It lives in the State, so that a copy of the
// State is a checkpoint and a fresh simulator (or another scheme) continues exactly.
struct SchemeHistory {
  std::string scheme;   // the scheme whose convention v() follows; empty: synchronous, fresh
  bool primed = false;  // leapfrog: v() holds v(n - 1/2) (the start-up half kick was applied)
  double last_h = 0;    // leapfrog: the step of the last kick, s (a change of step re-centres)
};

// Small evolving data of a plugged-in stage (a tuned cell size, a warm start), by stage name:
// part of the State, so checkpoints and copies carry it.
struct StageMemory {
  std::string stage;
  std::vector<double> values;
};

struct State {
  State() = default;
  explicit State(std::size_t points);

  std::span<Vec3> x() { return buffers.array(0); }  // [n] positions, m
  std::span<Vec3> v() { return buffers.array(1); }  // [n] velocities, m/s (see integrator)
  std::span<Vec3> f() { return buffers.array(2); }  // [n] force accumulator, N
  std::span<const Vec3> x() const { return buffers.array(0); }
  std::span<const Vec3> v() const { return buffers.array(1); }
  std::span<const Vec3> f() const { return buffers.array(2); }
  std::size_t size() const { return buffers.count(); }

  double time = 0;         // s, time of x
  std::uint64_t step = 0;  // steps taken since the start
  SchemeHistory history;
  std::vector<StageMemory> stage_memory;
  // The slot of `stage` (created empty on first use).
  std::vector<double>& memory(const std::string& stage);

  PointArrays buffers;
};

// Copies every value of `from` (positions, velocities, forces, time, step, the scheme's
// history, the stages' memory) into `to`, whose point arrays stay where they are (views of
// them, such as Python's, stay valid). Both have the same number of points.
void copy_values(const State& from, State& to);

// A 64-bit hash of positions, velocities, time, step, scheme history and stage memory: equal
// hashes mean bit-identical states.
std::uint64_t state_hash(const State& s);

}  // namespace maille
