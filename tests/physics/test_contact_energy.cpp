// The energy of contacts (Energies::contact, stats.csv's `contact` column): every stage that
// applies a conservative force reports its potential (Stage::energy), the model's conditional
// links theirs, and the two ways of storing a [[contact]] report the same energy.
//
// Against closed forms: a mass resting on a geometric plane stores (m g)^2 / (2 k); a pair
// pressed closer than the self-collision distance s stores k (s - d)^2 / 2, a particle over a
// face the same. Against an invariant: an undamped bounce on a plane conserves kinetic +
// gravity + contact to leapfrog's O(h^2), where kinetic + gravity alone loses the whole
// kinetic energy at the deepest point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"
#include "maille/state.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

Scene from_text(const std::string& text) {
  return test::scene_from_text(text, "test.toml");
}

Scene example(const std::string& name, const std::vector<std::string>& sets = {}) {
  auto s = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + name + ".toml", sets);
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

// One mass over a geometric ground plane (y <= 0), gravity along -y.
std::string on_plane(double height, double damping, double step) {
  std::ostringstream t;
  t << "[scene]\nname = \"bounce\"\n[simulation]\nstep = " << step
    << "\nduration = 1.0\n[fields]\ngravity = [0.0, -9.81, 0.0]\n"
    << "[[mass]]\nname = \"ball\"\nposition = [0.0, " << height << ", 0.0]\nmass = 0.5\n"
    << "[[obstacle]]\nname = \"ground\"\nshape = \"plane\"\nmethod = \"geometric\"\n"
    << "position = [0.0, 0.0, 0.0]\nstiffness = 5000.0\ndamping = " << damping
    << "\ncollides_with = [\"ball\"]\n";
  return t.str();
}

// A mass settled on the plane by the contact's damper: its depth is m g / k, and the penalty
// stores k d^2 / 2 = (m g)^2 / (2 k). Tolerance 1e-6 relative: after 4 s the damped motion
// (decay time 2 m / z = 0.05 s) is gone to far below that.
TEST(ContactEnergy, a_resting_mass_stores_its_weight_squared_over_2k) {
  Scene scene = from_text(on_plane(0.0, 20.0, 1e-4));
  Simulator sim(scene.model, scene.settings);
  ASSERT_TRUE(sim.run_steps(40000));
  const Energies e = sim.energies();
  const double mg = 0.5 * 9.81, k = 5000;
  EXPECT_NEAR(e.contact, mg * mg / (2 * k), 1e-6 * mg * mg / (2 * k));
  EXPECT_EQ(e.elastic, 0.0);
  EXPECT_NEAR(e.total(), e.kinetic + e.gravity + e.contact, 1e-15);
}

// An undamped bounce: kinetic + gravity + contact is leapfrog's shadow energy, constant to
// O((omega h)^2) with omega = sqrt(k / m) = 100 rad/s and h = 1e-5 s: 1e-6 of the drop's
// m g H; bounded here by 1e-4 of it. Without the contact's share the sum dips by the whole
// kinetic energy at the deepest point (the test shows the share is what closes the balance).
TEST(ContactEnergy, an_undamped_bounce_conserves_kinetic_gravity_and_contact) {
  Scene scene = from_text(on_plane(0.05, 0.0, 1e-5));
  Simulator sim(scene.model, scene.settings);
  const Energies start = sim.energies();
  const double scale = 0.5 * 9.81 * 0.05;
  double worst = 0, worst_without_contact = 0, most_contact = 0;
  for (int k = 0; k < 400; ++k) {  // 0.2 s: down (0.1 s), the bounce, and back up
    ASSERT_TRUE(sim.run_steps(50));
    const Energies e = sim.energies();
    worst = std::max(worst, std::abs(e.total() - start.total()));
    worst_without_contact =
        std::max(worst_without_contact, std::abs(e.total() - e.contact - start.total()));
    most_contact = std::max(most_contact, e.contact);
  }
  EXPECT_LT(worst, 1e-4 * scale);
  EXPECT_GT(most_contact, 0.5 * scale);  // the deepest sample holds most of the drop's energy
  EXPECT_GT(worst_without_contact, 0.5 * scale);
}

// Two free particles of one [self_collision] group, 4 mm apart with s = 10 mm, no gravity:
// k (s - d)^2 / 2 at the start, before anything moved.
TEST(ContactEnergy, a_pressed_pair_stores_k_s_minus_d_squared_over_2) {
  Scene scene = from_text(R"(
[scene]
name = "pair"
[simulation]
step = 1e-4
duration = 1.0
[[mass]]
name = "a"
position = [0.0, 0.0, 0.0]
[[mass]]
name = "b"
position = [0.004, 0.0, 0.0]
[self_collision]
groups = ["a", "b"]
radius = 0.01
stiffness = 800.0
)");
  Simulator sim(scene.model, scene.settings);
  const double gap = 0.01 - 0.004;
  EXPECT_NEAR(sim.energies().contact, 0.5 * 800 * gap * gap, 1e-12);
}

// Two 2 x 2 cloths (one face pair each, 10 cm wide), the upper 4 mm over the lower, with
// primitive = "triangles" and s = 10 mm: each of the 8 particles touches the other cloth's
// corner straight across (one contact: the corner is shared by the faces, counted once), and
// the 4 pairs of particles straight across are closer than s too. 12 contacts at d = 4 mm.
TEST(ContactEnergy, a_cloth_over_a_cloth_stores_every_particle_face_contact_once) {
  std::string cloth = R"(
[[flag]]
name = "NAME"
origin = [0.0, Y, 0.0]
along = [1.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
width = 0.1
height = 0.1
resolution = [2, 2]
mass = 0.01
stiffness = 100.0
fixed = "none"
)";
  auto make = [&](const char* name, const char* y) {
    std::string c = cloth;
    c.replace(c.find("NAME"), 4, name);
    c.replace(c.find("Y"), 1, y);
    return c;
  };
  Scene scene = from_text(R"(
[scene]
name = "stack"
[simulation]
step = 1e-4
duration = 1.0
)" + make("lower", "0.0") +
                          make("upper", "0.004") + R"(
[self_collision]
groups = ["lower", "upper"]
primitive = "triangles"
radius = 0.01
topological_radius = 0
stiffness = 800.0
)");
  Simulator sim(scene.model, scene.settings);
  const double gap = 0.01 - 0.004;
  EXPECT_NEAR(sim.energies().contact, 12 * 0.5 * 800 * gap * gap, 1e-12);
}

// [[contact]] as stored conditional links and by the broad phase: the same pairs under the same
// law, so the same contact energy; the trajectories differ only by the rounding of a different
// summation order (test_group_contact.cpp), so the energies agree to 1e-9 of the scene's
// energy. Each example is sampled while its contacts act.
TEST(ContactEnergy, links_and_broad_phase_report_the_same_energy) {
  struct Case {
    const char* name;
    int first, steps;  // first contacts near step `first` (test_group_contact.cpp); then 1000
  };
  for (const Case c : {Case{"lattice_balls_collide", 4200, 1000}, Case{"hanging_net", 2800, 1000},
                       Case{"rope_bridge", 6100, 1000}}) {
    SCOPED_TRACE(c.name);
    Scene links = example(c.name, {"contact[0].method=links"});
    Scene broad = example(c.name, {"contact[0].method=broad_phase"});
    Simulator a(links.model, links.settings), b(broad.model, broad.settings);
    ASSERT_TRUE(a.run_steps(std::uint64_t(c.first)));
    ASSERT_TRUE(b.run_steps(std::uint64_t(c.first)));
    double most_contact = 0;
    for (int k = 0; k < 10; ++k) {
      ASSERT_TRUE(a.run_steps(std::uint64_t(c.steps / 10)));
      ASSERT_TRUE(b.run_steps(std::uint64_t(c.steps / 10)));
      const Energies ea = a.energies(), eb = b.energies();
      const double scale = std::abs(ea.kinetic) + std::abs(ea.elastic) + std::abs(ea.gravity) +
                           std::abs(ea.contact) + 1e-12;
      EXPECT_NEAR(ea.contact, eb.contact, 1e-9 * scale) << "sample " << k;
      EXPECT_NEAR(ea.total(), eb.total(), 1e-9 * scale) << "sample " << k;
      most_contact = std::max(most_contact, ea.contact);
    }
    EXPECT_GT(most_contact, 0.0) << "no contact acted: the comparison says nothing";
  }
}

// stats.csv, the Python module and the page size their rows by kEnergyColumns.
TEST(ContactEnergy, the_energy_column_count_is_for_each_energys) {
  std::size_t n = 0;
  for_each_energy(Energies{}, [&](const char*, double) { ++n; });
  EXPECT_EQ(n, kEnergyColumns);
}

}  // namespace
