#include "shaders.hpp"

#include "gpu_glsl.hpp"
#include "gpu_layout.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// The head of every kernel: version, work group, the records, the shared laws' prelude (the
// scalar is float here) and packed-vec3 helpers.
std::string head(std::initializer_list<Buf> used) {
  std::string s =
      "#version 450 core\nlayout(local_size_x = " + std::to_string(kGroupSize) + ") in;\n";
  s += glsl_records();
  s += glsl_buffers(used);
  s += glsl::kernel_prelude;
  return s;
}

}  // namespace

// The switch over the model's kinds, generated: kind k calls its shared law (with the form's
// suffix) with its first `fields` parameters, then the form's extra arguments.
std::string link_switch_function(const std::vector<KindLaw>& kinds, const LinkSwitch& form) {
  std::string s = std::string(form.type) + " " + std::string(form.name) +
                  "(uint kind, vec3 xa, vec3 xb, vec3 va, vec3 vb, vec4 p" +
                  std::string(form.extra_params) + ") {\n  switch (kind) {\n";
  const char* component[] = {"p.x", "p.y", "p.z", "p.w"};
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    s += "    case " + std::to_string(k) + "u: return " + kinds[k].law + std::string(form.suffix) +
         "(xa, xb, va, vb";
    for (int f = 0; f < kinds[k].fields; ++f) s += std::string(", ") + component[f];
    s += std::string(form.extra_args) + ");\n";
  }
  s += "  }\n  return " + std::string(form.type) + "(0.0);\n}\n";
  return s;
}

std::string link_force_function(const std::vector<KindLaw>& kinds) {
  return link_switch_function(kinds, {"vec3", "link_force", "", "", ""});
}

std::string kernel_head(std::initializer_list<Buf> used) {
  return head(used);
}

std::string kernel_source(std::initializer_list<Buf> used,
                          std::initializer_list<std::string_view> parts) {
  std::string s = head(used);
  for (const std::string_view part : parts) s += part;
  return s;
}

std::string forces_shader(const std::vector<KindLaw>& kinds) {
  return kernel_source(
      {Buf::x, Buf::v, Buf::f, Buf::inv_mass, Buf::mass, Buf::adjacency_offset, Buf::adjacency,
       Buf::link_params, Buf::face_offset, Buf::face_of_point, Buf::face_force},
      {shared::link_laws, link_force_function(kinds), glsl::adjacency, glsl::forces});
}

std::string faces_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::face_corner, Buf::face_force},
                       {shared::wind_law, glsl::faces});
}

std::string integrate_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::f, Buf::inv_mass, Buf::health}, {glsl::integrate});
}

std::string drive_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::driven}, {glsl::drive});
}

}  // namespace maille::gpu
