// The GPU's structured layout for grid cloth: see gpu_structured.hpp.
#include "gpu_structured.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <stdexcept>
#include <utility>

#include "../render/gl_program.hpp"
#include "gl_buffers.hpp"
#include "gpu_glsl.hpp"
#include "gpu_layout.hpp"
#include "maille/detail/structured_grid.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

constexpr std::uint32_t kPerLink = 0xffffffffu;        // a family whose links' parameters differ
constexpr std::uint32_t kMostBefore = (1u << 20) - 1;  // other links before the stencil (bits 12+)
constexpr std::size_t kFamilies = detail::StructuredGrid::kFamilies.size();
static_assert(kFamilies == 6, "the word per grid point holds 2 x 6 bits, the kernel 12 calls");
// Every family's second end follows its first (dj > 0, or dj = 0 and di > 0): positive offsets.
static_assert([] {
  for (const auto& [di, dj] : detail::StructuredGrid::kFamilies)
    if (dj < 0 || (dj == 0 && di <= 0)) return false;
  return true;
}());
enum Uniform : unsigned {  // GpuStructured::loc_ has one int each
  u_count,
  u_first,
  u_nx,
  u_local,
  u_family_set,
  u_gravity,
  u_drag,
  u_wind,
  u_others,
  uniforms
};
constexpr const char* kUniformNames[uniforms] = {"u_count", "u_first",      "u_nx",
                                                 "u_local", "u_family_set", "u_gravity",
                                                 "u_drag",  "u_wind",       "u_others"};

// The stencil from the CPU's family table, as GLSL. kOrder: the 12 bits in the storage order of
// structured_grid.hpp (a point's links sorted by the row of their first end, then family, then
// the column of their first end); bit f: the family-f link leaving the point, bit 6 + f: the one
// reaching it. The kernel loops over them with one copy of the law (unrolled into 12 copies it
// ran 20 to 30 % slower on llvmpipe).
std::string stencil_order() {
  struct Call {
    std::array<int, 3> key;  // row of the first end (relative), family, its column (relative)
    unsigned bit;
  };
  std::vector<Call> calls;
  for (std::size_t f = 0; f < kFamilies; ++f) {
    const auto [di, dj] = detail::StructuredGrid::kFamilies[f];
    calls.push_back({{0, int(f), 0}, unsigned(f)});
    calls.push_back({{-dj, int(f), -di}, unsigned(f) + 6u});
  }
  std::sort(calls.begin(), calls.end(), [](const Call& p, const Call& q) { return p.key < q.key; });
  std::string order = "const uint kOrder[12] = uint[12](";
  for (std::size_t n = 0; n < calls.size(); ++n)
    order += std::to_string(calls[n].bit) + (n + 1 < calls.size() ? "u, " : "u);\n");
  return order;
}

// The families' index offsets di + dj nx (positive: the builders' orientation), a local array
// filled once per invocation rather than products in the loop (on llvmpipe the two measured the
// same within 3 %).
std::string stencil_offsets() {
  std::string out = "uint offset[6] = uint[6](";
  for (std::size_t f = 0; f < kFamilies; ++f) {
    const auto [di, dj] = detail::StructuredGrid::kFamilies[f];
    std::string o = dj == 0 ? "" : dj == 1 ? "u_nx" : std::to_string(dj) + "u * u_nx";
    if (di != 0)
      o += (o.empty() ? "" : di > 0 ? " + " : " - ") + std::to_string(std::abs(di)) + "u";
    out += o + (f + 1 < kFamilies ? ", " : ");");
  }
  return out;
}

// The kernel: one invocation per grid point. The stencil's links are visited in the general
// path's order (gpu_structured.hpp): bit 6 + f is the link of family f reaching this point as
// its second end, bit f the one leaving it as its first end.
std::string structured_shader(const KindLaw& stencil, const std::vector<KindLaw>& kinds) {
  std::string s =
      kernel_head({Buf::x, Buf::v, Buf::f, Buf::inv_mass, Buf::mass, Buf::link_params,
                   Buf::face_offset, Buf::face_of_point, Buf::face_force, Buf::grid_point,
                   Buf::grid_other_offset, Buf::grid_other, Buf::grid_link_set});
  s += shared::link_laws;
  s += link_force_function(kinds);
  const char* component[] = {"p.x", "p.y", "p.z", "p.w"};
  s += "vec3 stencil_force(vec3 xa, vec3 xb, vec3 va, vec3 vb, vec4 p) {\n  return " + stencil.law +
       "(xa, xb, va, vb";
  for (int f = 0; f < stencil.fields; ++f) s += std::string(", ") + component[f];
  s += ");\n}\n";
  s += glsl::structured;
  s.replace(s.find("@TABLES@"), 8, stencil_order());
  s.replace(s.find("@OFFSETS@"), 9, stencil_offsets());
  return s;
}

int family_of(int di, int dj) {
  for (std::size_t f = 0; f < kFamilies; ++f)
    if (detail::StructuredGrid::kFamilies[f][0] == di &&
        detail::StructuredGrid::kFamilies[f][1] == dj)
      return int(f);
  return -1;
}

}  // namespace

struct GpuStructured::Grid {
  PointGrid points;
  std::uint32_t local = 0;  // its first point in the grid buffers
  std::array<std::uint32_t, kFamilies> family_set{};
  bool others = false;  // some point has links off the stencil
};

// The layouts by the names MAILLE_GPU_LAYOUT and `maille info` spell.
constexpr std::pair<GridLayout, std::string_view> kLayoutNames[] = {
    {GridLayout::automatic, "auto"},
    {GridLayout::structured, "structured"},
    {GridLayout::general, "general"}};

GridLayout grid_layout_from_environment() {
  const char* value = std::getenv("MAILLE_GPU_LAYOUT");
  if (!value || !*value) return GridLayout::automatic;
  for (const auto& [layout, name] : kLayoutNames)
    if (name == value) return layout;
  throw std::invalid_argument("MAILLE_GPU_LAYOUT = '" + std::string(value) +
                              "': expected auto, structured or general");
}

std::string_view to_string(GridLayout layout) {
  for (const auto& [l, name] : kLayoutNames)
    if (l == layout) return name;
  return "auto";
}

std::unique_ptr<GpuStructured> GpuStructured::make(const Model& m, const LinkSets& sets,
                                                   const std::vector<KindLaw>& kinds,
                                                   GridLayout layout, GpuStructured* previous) {
  static_assert(sizeof(GpuStructured::loc_) / sizeof(int) == uniforms);
  if (layout == GridLayout::general) return nullptr;
  const auto& pools = m.links.pools();
  // The stencil runs one pool's structured links: the first pool that has any.
  std::size_t stencil = pools.size();
  for (std::size_t p = 0; p < pools.size() && stencil == pools.size(); ++p)
    if (pools[p]->structured_links() > 0 && sets.pool_kind[p] >= 0) stencil = p;
  if (stencil == pools.size()) return nullptr;
  std::unique_ptr<GpuStructured> out(new GpuStructured());
  std::uint32_t local = 0;
  for (const PointGrid& g : pools[stencil]->structured_grids()) {  // sorted by first point
    if (layout == GridLayout::automatic && std::uint64_t(g.nx) * g.ny < kStructuredMinPoints)
      continue;
    Grid grid;
    grid.points = g;
    grid.local = local;
    grid.family_set.fill(0);
    out->grids_.push_back(grid);
    local += g.nx * g.ny;
  }
  if (out->grids_.empty()) return nullptr;
  auto& grids = out->grids_;
  // The grid point of a model point (or none).
  auto locate = [&](std::uint32_t p) -> std::int64_t {
    const auto it =
        std::upper_bound(grids.begin(), grids.end(), p,
                         [](std::uint32_t q, const Grid& g) { return q < g.points.first; });
    if (it == grids.begin()) return -1;
    const Grid& g = *(it - 1);
    const std::uint32_t k = p - g.points.first;
    return k < g.points.nx * g.points.ny ? std::int64_t(g.local) + k : -1;
  };

  // The stencil's links: existence bits, parameter sets per link, uniform families.
  std::vector<std::uint32_t> word(local, 0), link_set(std::size_t(local) * kFamilies, kPerLink);
  std::vector<std::array<std::uint32_t, kFamilies>> first_set(grids.size());
  for (auto& f : first_set) f.fill(kPerLink);
  std::vector<std::array<bool, kFamilies>> uniform(grids.size());
  for (auto& u : uniform) u.fill(true);
  const LinkPoolBase& pool = *pools[stencil];
  const auto ends = pool.slot_ends();
  std::vector<char> taken(pool.structured_links(), 0);
  for (std::size_t s = 0; s < taken.size(); ++s) {
    const auto [a, b] = ends[s];
    const std::int64_t ka = locate(a), kb = locate(b);
    if (ka < 0 || kb < 0) continue;  // a grid automatic leaves to the general path
    const auto g = std::size_t(
        std::upper_bound(grids.begin(), grids.end(), a,
                         [](std::uint32_t q, const Grid& gr) { return q < gr.points.first; }) -
        grids.begin() - 1);
    const std::uint32_t nx = grids[g].points.nx, first = grids[g].points.first;
    const int f = family_of(int((b - first) % nx) - int((a - first) % nx),
                            int((b - first) / nx) - int((a - first) / nx));
    if (f < 0) continue;
    taken[s] = 1;
    word[std::size_t(ka)] |= 1u << f;
    word[std::size_t(kb)] |= 1u << (6 + f);
    const std::uint32_t set = sets.set_of_slot[sets.pool_base[stencil] + s];
    link_set[std::size_t(ka) * kFamilies + std::size_t(f)] = set;
    if (first_set[g][f] == kPerLink) first_set[g][f] = set;
    uniform[g][f] = uniform[g][f] && first_set[g][f] == set;
  }
  bool per_link = false;
  for (std::size_t g = 0; g < grids.size(); ++g)
    for (std::size_t f = 0; f < kFamilies; ++f) {
      grids[g].family_set[f] =
          uniform[g][f] ? (first_set[g][f] == kPerLink ? 0 : first_set[g][f]) : kPerLink;
      per_link = per_link || !uniform[g][f];
    }
  if (!per_link) link_set.clear();

  // The grid points' other links, in the adjacency's order (pool by pool, slot by slot): those
  // of the pools before the stencil's are summed before it (their count in bits 12+).
  std::vector<std::uint32_t> offset(std::size_t(local) + 1, 0);
  auto each_other = [&](auto&& visit) {
    for (std::size_t p = 0; p < pools.size(); ++p) {
      if (sets.pool_kind[p] < 0) continue;
      const auto kind = std::uint32_t(sets.pool_kind[p]);
      const auto slots = pools[p]->slot_ends();
      for (std::size_t s = 0; s < slots.size(); ++s) {
        if (p == stencil && s < taken.size() && taken[s]) continue;
        const std::uint32_t set = sets.set_of_slot[sets.pool_base[p] + s];
        const auto [a, b] = slots[s];
        if (const std::int64_t k = locate(a); k >= 0)
          visit(std::size_t(k), Adjacent{b, kind, set}, p < stencil);
        if (const std::int64_t k = locate(b); k >= 0)
          visit(std::size_t(k), Adjacent{a, kind | kEndIsB, set}, p < stencil);
      }
    }
  };
  std::vector<std::uint32_t> before(local, 0);
  each_other([&](std::size_t k, const Adjacent&, bool early) {
    ++offset[k + 1];
    before[k] += early;
  });
  for (std::size_t k = 0; k < local; ++k) {
    if (before[k] > kMostBefore) return nullptr;  // a point with a million other links: general
    word[k] |= before[k] << 12;
    offset[k + 1] += offset[k];
  }
  for (Grid& g : grids)
    g.others = offset[std::size_t(g.local) + g.points.nx * g.points.ny] > offset[g.local];
  std::vector<Adjacent> others(offset[local]);
  std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
  each_other([&](std::size_t k, const Adjacent& e, bool) { others[fill[k]++] = e; });

  // The general kernel's ranges: the points between the grids.
  std::uint32_t next = 0;
  for (const Grid& g : grids) {
    if (g.points.first > next) out->general_.push_back({next, g.points.first - next});
    next = g.points.first + g.points.nx * g.points.ny;
  }
  if (m.points.size() > next)
    out->general_.push_back({next, std::uint32_t(m.points.size()) - next});

  // A reload (an edit) keeps the previous load's buffers and, for the same source, its program:
  // the viewer's sliders reload the device between steps.
  if (previous && previous->buffers_[0]) {
    std::swap(out->buffers_, previous->buffers_);
  } else {
    glCreateBuffers(4, out->buffers_);
  }
  upload(out->buffers_[0], word, GL_STATIC_DRAW);
  upload(out->buffers_[1], offset, GL_STATIC_DRAW);
  upload(out->buffers_[2], others, GL_STATIC_DRAW);
  upload(out->buffers_[3], link_set, GL_STATIC_DRAW);
  out->source_ = structured_shader(kinds[std::size_t(sets.pool_kind[stencil])], kinds);
  if (previous && previous->program_ && previous->source_ == out->source_) {
    std::swap(out->program_, previous->program_);
    std::copy(std::begin(previous->loc_), std::end(previous->loc_), std::begin(out->loc_));
  } else {
    out->program_ = render::link_compute_program("gpu structured forces", out->source_);
    for (unsigned u = 0; u < uniforms; ++u)
      out->loc_[u] = glGetUniformLocation(out->program_, kUniformNames[u]);
  }
  if (out->grids_.size() == 1) out->set_grid(out->grids_[0]);
  return out;
}

GpuStructured::~GpuStructured() {
  if (program_) glDeleteProgram(program_);
  if (buffers_[0]) glDeleteBuffers(4, buffers_);  // none after forget(): no GL call
}

void GpuStructured::forget() {
  program_ = 0;
  std::fill(std::begin(buffers_), std::end(buffers_), 0u);
}

std::vector<StructuredGridInfo> GpuStructured::grids() const {
  std::vector<StructuredGridInfo> out;
  for (const Grid& g : grids_) out.push_back({g.points.first, g.points.nx, g.points.ny});
  return out;
}

void GpuStructured::evaluate(const Vec3& g, float drag, bool wind) {
  for (unsigned k = 0; k < 4; ++k)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unsigned(Buf::grid_point) + k, buffers_[k]);
  glProgramUniform3f(program_, loc_[u_gravity], float(g.x), float(g.y), float(g.z));
  glProgramUniform1f(program_, loc_[u_drag], drag);
  glProgramUniform1i(program_, loc_[u_wind], wind);
  glUseProgram(program_);
  for (const Grid& grid : grids_) {
    if (grids_.size() > 1) set_grid(grid);  // one grid's were set at load
    const std::uint32_t n = grid.points.nx * grid.points.ny;
    glDispatchCompute((n + kGroupSize - 1) / kGroupSize, 1, 1);
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GpuStructured::set_grid(const Grid& grid) {
  glProgramUniform1ui(program_, loc_[u_count], grid.points.nx * grid.points.ny);
  glProgramUniform1ui(program_, loc_[u_first], grid.points.first);
  glProgramUniform1ui(program_, loc_[u_nx], grid.points.nx);
  glProgramUniform1ui(program_, loc_[u_local], grid.local);
  glProgramUniform1i(program_, loc_[u_others], grid.others);
  glProgramUniform1uiv(program_, loc_[u_family_set], GLsizei(kFamilies), grid.family_set.data());
}

}  // namespace maille::gpu
