// Self-collision (Theme 1): the free points of some groups repel each other when closer than a
// contact distance s, through the conditional spring-damper law, with mesh neighbours excluded.
//
//   broad phase   candidate pairs: brute force (the reference), a uniform grid over the bounding
//                 box (counting sort into cells), a hashed grid (spatial hashing: memory follows
//                 the particles, not the box), or a hierarchical grid (an adaptive octree: cells
//                 split where particles crowd); all four yield exactly the pairs closer than s
//   exclusion     pairs at graph distance <= R links never interact: `matrix` stores, per
//                 particle, the sorted set of particles within R (compact: O(n) memory, not n^2
//                 bits); `signature` gives each grid cell the (i, j) box of its particles' grid
//                 indices, skips cell pairs whose particles are all within R of each other, and
//                 tests the rest by a stencil of index offsets (grid cloth) or by the matrix
//   response      per close pair, the conditional spring-damper (rest length s, so the force is
//                 continuous at s) and optional Coulomb-like friction on the tangential velocity
//   triangles     optionally, particles also repel from the surface's triangles closer than s
//                 (not their own neighbourhood): coarse cloth cannot pass between its particles
//
// Determinism: each particle sums its contacts in the order of its partners' indices, whatever
// the broad phase, the cell size or the thread count: trajectories are bit-identical across
// them. Installed by a `[self_collision]` scene table (docs/scene-format.md).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "maille/model.hpp"
#include "maille/stage.hpp"

namespace maille {

enum class BroadPhase : std::uint8_t { brute, uniform, hashed, hierarchical };
enum class Exclusion : std::uint8_t { none, matrix, signature };
enum class Primitive : std::uint8_t { points, triangles };

struct SelfCollisionSettings {
  std::vector<std::string> groups;  // empty: every group with free points
  Real radius = 0;           // s, m; 0: half the smallest rest length among the groups' links
  Real stiffness = 500;      // N/m
  Real damping = Real(0.5);  // N.s/m
  Real friction = 0;         // tangential coefficient (Coulomb-like), >= 0
  BroadPhase broad_phase = BroadPhase::uniform;
  Real cell_size = 0;  // m, >= radius; 0: "auto" (measured, see the tuner)
  Exclusion exclusion = Exclusion::signature;
  int topological_radius = 2;  // R, links
  // points: particle-particle contacts; triangles: also particle-triangle proximity (the
  // groups' surface faces), so that a coarse cloth cannot pass through itself between particles
  Primitive primitive = Primitive::points;
};

std::string_view to_string(BroadPhase b);
std::string_view to_string(Exclusion e);

// What one pass found (for tests, studies and the profile).
struct SelfCollisionStats {
  std::uint64_t candidate_pairs = 0;    // pairs whose distance was tested
  std::uint64_t contacts = 0;           // pairs closer than s and not excluded
  std::uint64_t excluded = 0;           // pairs closer than s removed by the exclusion
  std::uint64_t skipped_cells = 0;      // cell pairs skipped whole by signatures
  std::uint64_t triangle_contacts = 0;  // particle-triangle contacts (primitive = triangles)
  std::uint64_t occupied_cells = 0;
  double cell_size = 0;  // m, the resolution used (0 for brute force)
};

class SelfCollision;

// The force stage ("self_collision", Phase::forces). Throws std::invalid_argument for groups
// that do not exist or hold no free point, or a cell size below the radius.
std::unique_ptr<Stage> make_self_collision_stage(const Model& m, const SelfCollisionSettings& s);

// Below this tangential speed, friction turns viscous (contact_friction_law's `slip`), m/s.
inline constexpr Real kSelfCollisionSlip = Real(1e-3);

// For device backends that run the stage themselves (the GPU's uniform grid, src/gpu): what a
// self-collision stage runs now. `settings` is null when `st` is not a self-collision stage;
// otherwise it holds the live options (exclusion, broad phase) and the resolved radius (> 0).
// The view is valid until the stage's next model_changed.
struct SelfCollisionView {
  const SelfCollisionSettings* settings = nullptr;
  bool enabled = false;                      // the live option "enabled"
  std::span<const std::uint32_t> particles;  // the colliding points: the groups' free points
};
SelfCollisionView self_collision_view(const Stage& st);

// The pairs the topological exclusion removes, as rows (CSR over local indices: positions in
// `particles`), whatever the stage's exclusion mode: the matrix form, which removes exactly the
// pairs the signature form removes (test unit.SelfCollision.ExclusionRemovesExactly...).
// `particles` sorted; radius 0: empty rows.
struct ExclusionRows {
  std::vector<std::uint32_t> offset;   // [particles + 1]: row a is [offset[a], offset[a + 1])
  std::vector<std::uint32_t> partner;  // local indices, sorted in each row
};
ExclusionRows self_collision_exclusion_rows(const Model& m,
                                            std::span<const std::uint32_t> particles,
                                            int topological_radius);
// The bytes the matrix exclusion will hold for `particles` (sorted global ids) at the given
// radius, before building it: the longest row of a bounded search from up to 64 of them, times
// their number, 4 bytes each, plus the row offsets and the search's arrays (adjacency, marks).
// The scene reader refuses a [self_collision] table whose estimate exceeds the memory budget.
std::uint64_t self_collision_exclusion_bytes(const Model& m,
                                             std::span<const std::uint32_t> particles,
                                             int topological_radius);

// The engine behind the stage, usable alone (tests, studies, benchmarks).
class SelfCollisionEngine {
 public:
  SelfCollisionEngine(const Model& m, SelfCollisionSettings s);
  ~SelfCollisionEngine();
  SelfCollisionEngine(SelfCollisionEngine&&) noexcept;

  // Close, non-excluded pairs (global point ids, a < b, sorted) at positions x (all points).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> close_pairs(const Vec3* x, int threads);
  // Adds contact forces into f (all points); returns what the pass found.
  SelfCollisionStats apply(const Vec3* x, const Vec3* v, Vec3* f, int threads);
  const SelfCollisionSettings& settings() const;
  std::size_t particles() const;
  std::size_t exclusion_bytes() const;  // memory held by the exclusion structures
  // Auto cell size: the tuner's last choice, its candidates' measured times and the model's
  // P n^2 predictions (for the study and the log).
  struct TuneRecord {
    double cell_size = 0, measured_ns = 0, predicted = 0;
    std::uint64_t occupied = 0;
    bool chosen = false;  // the tuner kept this size
  };
  const std::vector<TuneRecord>& last_tuning() const;
  void set_broad_phase(BroadPhase b);
  void set_exclusion(Exclusion e);
  void set_cell_size(Real c);  // 0: auto

 private:
  std::unique_ptr<SelfCollision> impl_;
};

}  // namespace maille
