#include "maille/state.hpp"

#include <cstring>
#include <new>

namespace maille {

namespace {
constexpr std::size_t kPage = 4096;
constexpr std::size_t kStagger = 192;  // bytes added per array so bases differ modulo 4 KiB
constexpr std::size_t kAlign = 64;
}  // namespace

PointArrays::PointArrays(std::size_t count, int arrays) : count_(count), arrays_(arrays) {
  const std::size_t bytes = count * sizeof(Vec3);
  stride_bytes_ = (bytes + kPage - 1) / kPage * kPage + kStagger;
  const std::size_t total = stride_bytes_ * static_cast<std::size_t>(arrays) + kAlign;
  storage_ = std::make_unique<std::byte[]>(total);  // value-initialised: all zeros
}

PointArrays::PointArrays(const PointArrays& other) : PointArrays(other.count_, other.arrays_) {
  for (int a = 0; a < arrays_; ++a)
    if (count_ > 0) std::memcpy(base(a), other.base(a), count_ * sizeof(Vec3));
}

PointArrays& PointArrays::operator=(const PointArrays& other) {
  if (this != &other) *this = PointArrays(other);
  return *this;
}

Vec3* PointArrays::base(int which) const {
  auto raw = reinterpret_cast<std::uintptr_t>(storage_.get());
  raw = (raw + kAlign - 1) / kAlign * kAlign;
  return std::launder(
      reinterpret_cast<Vec3*>(raw + stride_bytes_ * static_cast<std::size_t>(which)));
}

State::State(std::size_t points) : buffers(points, 3) {}

void copy_values(const State& from, State& to) {
  std::memcpy(to.x().data(), from.x().data(), from.size() * sizeof(Vec3));
  std::memcpy(to.v().data(), from.v().data(), from.size() * sizeof(Vec3));
  std::memcpy(to.f().data(), from.f().data(), from.size() * sizeof(Vec3));
  to.time = from.time;
  to.step = from.step;
  to.history = from.history;
  to.stage_memory = from.stage_memory;  // element by element: capacity kept
}

std::vector<double>& State::memory(const std::string& stage) {
  for (auto& m : stage_memory)
    if (m.stage == stage) return m.values;
  stage_memory.push_back({stage, {}});
  return stage_memory.back().values;
}

std::uint64_t state_hash(const State& s) {
  // FNV-1a over the raw bytes: any bit difference shows.
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(s.x().data(), s.size() * sizeof(Vec3));
  mix(s.v().data(), s.size() * sizeof(Vec3));
  mix(&s.time, sizeof s.time);
  mix(&s.step, sizeof s.step);
  mix(s.history.scheme.data(), s.history.scheme.size());
  mix(&s.history.primed, sizeof s.history.primed);
  mix(&s.history.last_h, sizeof s.history.last_h);
  for (const auto& m : s.stage_memory) {
    mix(m.stage.data(), m.stage.size());
    mix(m.values.data(), m.values.size() * sizeof(double));
  }
  return h;
}

}  // namespace maille
