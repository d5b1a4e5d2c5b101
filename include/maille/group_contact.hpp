// Contacts between groups (`[[contact]] between = [A, B]`): the CORDIS conditional spring-damper
// between every point of A and every point of B (at least one end free), without one link per
// pair. Each step a uniform grid (the self-collision broad phase, cells of the threshold) finds
// the pairs closer than the threshold; only those exert a force, exactly as the all-pairs
// conditional links would (a pair at or beyond its threshold exerts nothing).
//
//   results    each point sums its contacts in its partners' order and adds the sum to its force
//              once, after the link and field forces: the same law and the same pairs as the
//              conditional links of `method = "links"`, summed in another order, so the two
//              agree to rounding (tests/physics/test_group_contact.cpp bounds it); one and two
//              threads give bit-identical trajectories
//   counters   active pairs are added to `active_conditional_links`, as the links counted them;
//              `group_contact_candidates` counts the pairs whose distance was tested
//   implicit   for implicit schemes the stage offers this step's pairs within the threshold plus
//              the step's motion margin as conditional links (Stage::find_contacts,
//              contact_set.hpp), like self-collision's contacts
//
// Installed by the [[contact]] table's registry entry (src/scene/contact_table.cpp, a gathered
// table), one stage (kGroupContactStage) for every [[contact]] table of a scene whose method is
// "broad_phase" (the default).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/names.hpp"
#include "maille/stage.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

// The stage's name (its profile column ns_group_contacts, stats and messages) and phase.
inline constexpr StageInfo kGroupContactStage{"group_contacts", Phase::forces};

// How [[contact]] finds its pairs (scene key `method`).
enum class ContactMethod : std::uint8_t { broad_phase, links };
template <>
struct NameTable<ContactMethod> {
  static constexpr std::string_view what = "contact method";
  static constexpr std::array<Name<ContactMethod>, 2> names{{
      {ContactMethod::broad_phase, "broad_phase", "pairs found each step by a grid"},
      {ContactMethod::links, "links",
       "one conditional link per pair, the CORDIS way, also run by the GPU"},
  }};
};

// One [[contact]] table, resolved. Its keys are declared in contact_keys().
struct GroupContactSpec {
  std::string a, b;      // group names (distinct groups, no shared point)
  Real stiffness = 0;    // k, N/m
  Real damping = 0;      // z, N.s/m
  Real threshold = 0;    // s, m: a pair acts while closer than s
  Real rest_length = 0;  // L0, m
  ContactMethod method = ContactMethod::broad_phase;  // the stage runs broad_phase specs only
};

// [[contact]]'s keys (stage_keys.hpp), declared in group_contact_keys.cpp: contact_tables()
// reads them, docs/scene-format.md's table is checked against them, `maille info` shows them.
std::span<const StageKey<GroupContactSpec>> contact_keys();

// The force stage. Throws std::invalid_argument for an unknown group, groups that share points,
// or a pair of groups without a free point.
std::unique_ptr<Stage> make_group_contact_stage(const Model& m,
                                                const std::vector<GroupContactSpec>& specs);

}  // namespace maille
