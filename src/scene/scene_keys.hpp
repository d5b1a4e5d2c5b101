// The keys of the scene's own tables ([scene], [simulation], [fields], [[mass]], [[fixed]],
// `drive`, [[link]], [[geometric_point]]), declared once (stage_keys.hpp): the scene reader reads
// them through these declarations and docs/scene-format.md's tables are generated from them
// (declared_tables(), `maille info --keys`; unit.StageKeys.* checks the docs row for row).
// Builders' keys are in builder_keys.cpp, sound's in audio_keys.cpp.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "maille/drive.hpp"
#include "maille/geometric_point.hpp"
#include "maille/obstacle.hpp"
#include "maille/scene.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<Scene>> scene_keys();                    // [scene]
std::span<const StageKey<SimulationSettings>> simulation_keys();  // [simulation]
std::span<const StageKey<Fields>> fields_keys();                  // [fields]

// [[mass]] and [[fixed]]: one explicit point as read (the drive is read by the reader).
struct PointTable {
  std::string name;
  Vec3 position{};
  Real mass = 1;
  Vec3 velocity{};
};
std::span<const StageKey<PointTable>> point_keys();
std::span<const StageKey<DrivePath>> drive_keys();  // `drive` (on [[fixed]] and builders)

// [[link]]: the keys every link has; the kind's parameters are its `fields` (link_kind.hpp),
// documented by link_kind_keys().
struct LinkTable {
  std::string kind;
};
std::span<const StageKey<LinkTable>> link_keys();

// [[geometric_point]]: a shape placed by an affine map.
struct GeometricPointTable {
  GeometricPoint point;
  Vec3 position{0, 0, 0}, rotation{0, 0, 0}, scale{1, 1, 1};
};
std::span<const StageKey<GeometricPointTable>> geometric_point_keys();

// [[link]] with kind = "geometric_contact": a geometric point (a) and a free mass or group (b).
struct GeometricContactTable {
  std::string a;
  GeometricContact contact;
  ContactNormal normal = ContactNormal::canonical;
};
std::span<const StageKey<GeometricContactTable>> geometric_contact_keys();

// [[obstacle]]'s `motion` sub-table (obstacle_table.cpp reads it; the obstacle's own keys are
// obstacle_keys()).
std::span<const StageKey<ObstacleMotion>> motion_keys();

}  // namespace maille
