// A compute kernel of the GPU backend: its program and its uniforms' locations (each looked up
// once, by name), shared by the step's kernels (gpu_backend.cpp), the self-collision grid
// (gpu_self_collision.hpp) and vertex block descent (gpu_vbd.hpp). The context must be current
// for every call but forget().
#pragma once

#include <functional>
#include <map>
#include <string>
#include <string_view>

#include "maille/mat3.hpp"
#include "maille/vec3.hpp"

namespace maille::gpu {

class Kernel {
 public:
  Kernel() = default;                                        // no program: run() must not be called
  Kernel(std::string_view name, const std::string& source);  // compiled and linked, or throws
  Kernel(Kernel&& o) noexcept;
  Kernel& operator=(Kernel&& o) noexcept;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;
  ~Kernel();
  // Its context is gone or not current: the destructor deletes nothing.
  void forget() { program_ = 0; }

  void set(const char* name, unsigned value);
  void set(const char* name, float value);
  void set_flag(const char* name, bool value);
  void set(const char* name, const Vec3& value);  // as float
  void set(const char* name, const float (&value)[3]);
  void set(const char* name, const float (&value)[4]);
  void set(const char* name, const Mat3& value);  // a mat3, as float: the same matrix in GLSL

  // `count` invocations (u_count) in `groups` work groups, then a barrier that makes its
  // storage writes visible to the next kernel. Nothing when there are no groups.
  void run(unsigned count, unsigned groups);
  // As many groups of kGroupSize as `count` needs (most kernels: one invocation per item).
  void run(unsigned count);

 private:
  int at(const char* name);

  unsigned program_ = 0;
  std::map<std::string, int, std::less<>> loc_;
};

}  // namespace maille::gpu
