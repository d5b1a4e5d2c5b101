// The geometric obstacle's kernels (gpu_obstacle.hpp): the CPU stage's law, pasted from
// include/maille/detail/obstacle_laws.glsl.
#include "gpu_glsl.hpp"
#include "gpu_obstacle.hpp"
#include "gpu_vbd_obstacles.hpp"
#include "shaders.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

std::string obstacle_contacts_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::f, Buf::ob_point},
                       {shared::obstacle_laws, glsl::obstacle_head, glsl::obstacle_contacts});
}

// The CPU solver's point-contact steps (implicit_vbd.cpp, GeometricObstacleStage's
// PointContacts), for the sweep, lag and first-touch kernels of gpu_vbd_shaders.cpp.
std::string vbd_obstacle_functions() {
  std::string s(shared::obstacle_laws);
  s += "#define OB_BISECTIONS " + std::to_string(kVbdBisections) + "\n";
  s += "#define OB_MAX_SAMPLES " + std::to_string(kVbdMaxSegmentSamples) + "\n";
  s += glsl::vbd_obstacle_functions;
  return s;
}

}  // namespace maille::gpu
