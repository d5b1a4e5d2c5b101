// Bullet's side of the peer comparison: the same cloth as a btSoftBody patch in a
// btSoftRigidDynamicsWorld, the sphere a static btRigidBody, stepped one fixed step at a time
// (stepSimulation(h, 0): no internal sub-stepping, no interpolation). Bullet is
// single-threaded here (no task scheduler is installed).
#include <btBulletDynamicsCommon.h>

#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <chrono>
#include <memory>
#include <sstream>

#include "peer.hpp"

namespace peer {

namespace {

// Everything one run owns, released in reverse order.
struct World {
  btSoftBodyRigidBodyCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  btSphereShape sphere_shape;
  std::unique_ptr<btRigidBody> sphere;
  btSoftBody* cloth = nullptr;

  explicit World(const PeerScene& s) : sphere_shape(btScalar(s.radius)) {
    world.setGravity(btVector3(0, btScalar(-s.gravity), 0));
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = btVector3(0, btScalar(-s.gravity), 0);
    info.m_broadphase = &broadphase;
    info.m_dispatcher = &dispatcher;
    info.m_sparsesdf.Initialize();

    // The sphere: mass 0 (static), at the origin.
    btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, &sphere_shape);
    sphere = std::make_unique<btRigidBody>(ci);
    world.addRigidBody(sphere.get());

    // The cloth: n x n nodes, node (i, j) = j * n + i (CreatePatch's order), corners at
    // (+-L/2, height, +-L/2). CreatePatch makes the structural links and, with gendiags, one
    // diagonal per cell; the other diagonal is added so shear is held by both, as in Maille.
    const btScalar h = btScalar(s.height), a = btScalar(s.side / 2);
    cloth =
        btSoftBodyHelpers::CreatePatch(info, btVector3(-a, h, -a), btVector3(a, h, -a),
                                       btVector3(-a, h, a), btVector3(a, h, a), s.n, s.n, 0, true);
    const int n = s.n;
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const int p = j * n + i;
        if (!cloth->checkLink(p, p + n + 1)) cloth->appendLink(p, p + n + 1);
        if (!cloth->checkLink(p + 1, p + n)) cloth->appendLink(p + 1, p + n);
      }
    cloth->setTotalMass(btScalar(s.mass));
  }
  ~World() {
    if (cloth) {
      world.removeSoftBody(cloth);
      delete cloth;
    }
    world.removeRigidBody(sphere.get());
  }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
};

template <class T, class V>
void set_if(T& field, V value) {
  if (value >= 0) field = static_cast<T>(value);
}

}  // namespace

std::string BulletSetting::describe() const {
  std::ostringstream d;
  d << "btSoftBody defaults";
  if (piterations >= 0) d << " piterations=" << piterations;
  if (citerations >= 0) d << " citerations=" << citerations;
  if (margin >= 0) d << " margin=" << margin;
  if (kDP >= 0) d << " kDP=" << kDP;
  if (kCHR >= 0) d << " kCHR=" << kCHR;
  if (kDF >= 0) d << " kDF=" << kDF;
  if (voxel >= 0) d << " sdf_voxel=" << voxel;
  return d.str();
}

std::string bullet_version() {
  const int v = btGetVersion();
  std::ostringstream s;
  s << v / 100 << '.' << v % 100 << (sizeof(btScalar) == 8 ? " double" : " float");
  return s.str();
}

std::string bullet_defaults() {
  PeerScene s;
  s.n = 4;
  World w(s);
  const btSoftBody::Config& c = w.cloth->m_cfg;
  std::ostringstream d;
  d << "piterations=" << c.piterations << " viterations=" << c.viterations
    << " diterations=" << c.diterations << " citerations=" << c.citerations << " kDP=" << c.kDP
    << " kDF=" << c.kDF << " kCHR=" << c.kCHR << " kVCF=" << c.kVCF << " timescale=" << c.timescale
    << " collisions=0x" << std::hex << c.collisions << std::dec
    << " margin=" << w.cloth->getCollisionShape()->getMargin()
    << " sdf_voxel=" << w.world.getWorldInfo().m_sparsesdf.m_defaultVoxelsz
    << " kLST=" << w.cloth->m_materials[0]->m_kLST << " kAST=" << w.cloth->m_materials[0]->m_kAST;
  return d.str();
}

RunResult run_bullet(const PeerScene& s, const BulletSetting& b, double step) {
  World w(s);
  btSoftBody::Config& c = w.cloth->m_cfg;
  set_if(c.piterations, b.piterations);
  set_if(c.citerations, b.citerations);
  set_if(c.kDP, b.kDP);
  set_if(c.kCHR, b.kCHR);
  set_if(c.kDF, b.kDF);
  if (b.margin >= 0) w.cloth->getCollisionShape()->setMargin(btScalar(b.margin));
  if (b.voxel > 0) {
    w.world.getWorldInfo().m_sparsesdf.setDefaultVoxelsz(btScalar(b.voxel));
    w.world.getWorldInfo().m_sparsesdf.Reset();
  }
  w.world.addSoftBody(w.cloth);

  ClothMeter meter(s, b.bounds);
  const auto steps = std::uint64_t(std::llround(s.duration / step));
  const auto get = [&](int p) {
    const btVector3& x = w.cloth->m_nodes[p].m_x;
    return std::array<double, 3>{double(x.x()), double(x.y()), double(x.z())};
  };
  using clock = std::chrono::steady_clock;
  clock::duration wall{};
  std::uint64_t done = 0;
  for (; done < steps; ++done) {
    const auto t0 = clock::now();
    w.world.stepSimulation(btScalar(step), 0);
    wall += clock::now() - t0;
    if (!meter.sample(get)) break;
  }
  return meter.finish(step, double(done) * step, std::chrono::duration<double>(wall).count());
}

}  // namespace peer
