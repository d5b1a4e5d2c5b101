// The base of the classes that own device objects (buffers, programs): a copy would delete them
// twice, so there is none (Jolt's NonCopyable).
#pragma once

namespace maille::gpu {

class NonCopyable {
 public:
  NonCopyable() = default;
  NonCopyable(const NonCopyable&) = delete;
  NonCopyable& operator=(const NonCopyable&) = delete;
};

}  // namespace maille::gpu
