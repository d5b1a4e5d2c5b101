// Self-collision: the free points of some groups repel each other when closer than a
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
//                 (not their own neighbourhood), and the triangles' edges from each other
//                 (edge_proximity.hpp): coarse cloth cannot pass between its particles, nor an
//                 edge through an edge when a wrung cloth crosses itself
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
#include "maille/names.hpp"
#include "maille/stage.hpp"

namespace maille {

enum class BroadPhase : std::uint8_t { brute, uniform, hashed, hierarchical };
enum class Exclusion : std::uint8_t { none, matrix, signature };
enum class Primitive : std::uint8_t { points, triangles };
enum class IntersectionCheck : std::uint8_t { off, stats, every_step };

template <>
struct NameTable<BroadPhase> {
  static constexpr std::string_view what = "broad phase";
  static constexpr std::array<Name<BroadPhase>, 4> names{{
      {BroadPhase::brute, "brute", "every pair tested: n(n-1)/2 (the reference)"},
      {BroadPhase::uniform, "uniform", "a uniform grid over the bounding box (counting sort)"},
      {BroadPhase::hashed, "hashed", "the same cells hashed: memory follows the particles"},
      {BroadPhase::hierarchical, "hierarchical", "an octree split where particles crowd"},
  }};
};
template <>
struct NameTable<Exclusion> {
  static constexpr std::string_view what = "exclusion";
  static constexpr std::array<Name<Exclusion>, 3> names{{
      {Exclusion::none, "none", "mesh neighbours collide too"},
      {Exclusion::matrix, "matrix", "per particle, the sorted list of particles within R links"},
      {Exclusion::signature, "signature", "grid stencils and cell signatures (else matrix rows)"},
  }};
};
template <>
struct NameTable<Primitive> {
  static constexpr std::string_view what = "primitive";
  static constexpr std::array<Name<Primitive>, 2> names{{
      {Primitive::points, "points", "particle-particle contacts"},
      {Primitive::triangles, "triangles", "also particle-triangle and edge-edge proximity"},
  }};
};

template <>
struct NameTable<IntersectionCheck> {
  static constexpr std::string_view what = "check";
  static constexpr std::array<Name<IntersectionCheck>, 3> names{{
      {IntersectionCheck::off, "off", "no count"},
      {IntersectionCheck::stats, "stats", "counted at the stats cadence (intersecting_pairs)"},
      {IntersectionCheck::every_step, "every_step",
       "counted every step; the run stops (exit 3) at the first crossing"},
  }};
};

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
  // How often the pairs of the groups' faces that cross are counted (intersections.hpp).
  IntersectionCheck check = IntersectionCheck::stats;
};

// What one pass found (for tests, studies and the profile).
struct SelfCollisionStats {
  std::uint64_t candidate_pairs = 0;    // pairs whose distance was tested
  std::uint64_t contacts = 0;           // pairs closer than s and not excluded
  std::uint64_t excluded = 0;           // pairs closer than s removed by the exclusion
  std::uint64_t skipped_cells = 0;      // cell pairs skipped whole by signatures
  std::uint64_t triangle_contacts = 0;  // particle-triangle contacts (primitive = triangles)
  std::uint64_t edge_contacts = 0;      // edge-edge contacts (primitive = triangles)
  std::uint64_t occupied_cells = 0;
  double cell_size = 0;  // m, the resolution used (0 for brute force)
};

class SelfCollision;
template <class S>
struct StageKey;  // stage_keys.hpp

// [self_collision]'s keys, declared once (src/collision/self/self_collision_keys.cpp): the scene
// reader, `maille info` and docs/scene-format.md's table read them.
std::span<const StageKey<SelfCollisionSettings>> self_collision_keys();

// The stage's name and phase, said once: the scene table's StageSpec and the stage report them.
inline constexpr StageInfo kSelfCollisionStage{"self_collision", Phase::forces};

// Checks the settings against the model without building anything (no grid, no exclusion rows):
// the groups exist and hold free points, the radius can be defaulted, the cell size is not below
// the radius. Resolves a radius of 0 to its default in `s`. The scene table and the engine's
// constructor both call it.
StageProblem resolve_self_collision(const Model& m, SelfCollisionSettings& s);

// The force stage (kSelfCollisionStage). Throws std::invalid_argument with the message of
// resolve_self_collision's problem.
std::unique_ptr<Stage> make_self_collision_stage(const Model& m, const SelfCollisionSettings& s);

// Below this tangential speed, friction turns viscous (contact_friction_law's `slip`), m/s.
inline constexpr Real kSelfCollisionSlip = Real(1e-3);

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
  // After apply() at x, primitive = "triangles": each colliding point's displacement bound for
  // the step, `share` of its distance to the faces and edges its Verlet lists hold and of the
  // radius, into bound[global id] (only lowered; the caller fills it with +inf). False when the
  // pass had no lists (primitive = "points", a list over its budget): nothing is bounded.
  bool motion_bounds(const Vec3* x, Real share, std::vector<Real>& bound) const;
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
