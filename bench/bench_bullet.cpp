// csim's lumped Moreau–Jean step against Bullet 3.24 (Debian's libbullet-dev, double precision), run
// alternately in one process (run by hand: build/bench/bench_bullet [repeats] [end_scale]).
//
// Printed: µs per step, median and min–max over the repeats, of
//   sdnv104-rigid  h = 1e-5, 10 s (1e6 steps): csim and Bullet, and their ratio;
//   incline-3d     h = 1e-5, 10 s: csim and Bullet, and their ratio;
//   sdnd100-a      h = 2e-6, 0.3 s: csim alone (a sphere on a spring held on a line: no Bullet model).
// end_scale (default 1) shortens every run, for a quick look. csim's figure is run_scene's wall time
// per step, probes, checks and energy balance included (what `csim run` costs); Bullet's is the loop of
// stepSimulation(h, 0, h) and a read of the position.
//
// What is the same in the two models of SDNV104 (scenes/sdnv104-rigid/scene.yaml):
//   a 1 m × 1 m shoe of 7000 kg on a rigid plane, pressed by 70 kN at its centre, pushed by 200 kN,
//   held by k = 24 kN/m along x (csim: two springs of k/2 at its corners (0.5, ±0.5); Bullet: the
//   force −k·dx applied at the centre before each step, the same force while the shoe does not turn),
//   Coulomb μ = 0.3 (Bullet multiplies the two bodies' frictions: 0.3 × 1), no restitution, no
//   gravity, fixed step h, one thread; motion in the plane (Bullet: linear factor (1, 1, 0), angular
//   factor (0, 0, 1)). incline-3d: a 10 kg cube of 0.2 m on a plane tilted by 20°, μ = 0.5, gravity.
// What differs:
//   - csim solves each step's contact problem exactly (PGS to a residual of 1e-12, exact local Coulomb
//     solves); Bullet's sequential impulses stop after m_numIterations = 10 sweeps (its default) and
//     regularize with ERP/CFM, split impulse on (its defaults). The exactness is what csim's step
//     buys: the printed extrema show Bullet's error on x1 = 2(F − μN)/k.
//   - Bullet's box–plane manifold keeps 4 points in space; csim's plane scene has 2 (the shoe's lower
//     corners); incline-3d has 4 in both.
//   - Bullet has a collision margin (0.04 m, inside the box) and a contact breaking threshold; csim's
//     box–plane gaps are exact (contact/narrow_phase.h).
#include "bench/spread.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

using csim::bench::Spread;
using csim::bench::spread;

struct CsimRun {
  double us_per_step;
  double first_extremum;  // the first check's value (x1 on SDNV104), NAN when absent
};

CsimRun run_csim(const csim::Scene& scene) {
  const csim::RunReport report = csim::run_scene(scene, {});
  const double steps = static_cast<double>(report.state.counters.steps);
  return {1e6 * report.wall_time / steps, report.checks.empty() ? NAN : report.checks.front().value};
}

// A Bullet world with a fixed plane (normal n, through the origin) and one box; the caller applies
// its forces. Its members are owned here, in the order Bullet needs them destroyed.
struct BulletWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  btStaticPlaneShape plane_shape;
  btBoxShape box_shape;
  std::unique_ptr<btRigidBody> plane, box;

  BulletWorld(const btVector3& normal, const btVector3& half_extents, double mass, const btTransform& box_pose,
              double box_friction)
      : plane_shape(normal, 0.0), box_shape(half_extents) {
    world.setGravity(btVector3(0, 0, 0));
    plane = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, &plane_shape));
    plane->setFriction(1.0);
    plane->setRestitution(0.0);
    world.addRigidBody(plane.get());
    btVector3 inertia;
    box_shape.calculateLocalInertia(mass, inertia);
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, &box_shape, inertia);
    info.m_startWorldTransform = box_pose;
    info.m_friction = box_friction;  // times the plane's 1
    info.m_restitution = 0.0;
    box = std::make_unique<btRigidBody>(info);
    box->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(box.get());
  }
  ~BulletWorld() {
    world.removeRigidBody(box.get());
    world.removeRigidBody(plane.get());
  }
};

struct BulletRun {
  double us_per_step;
  double first_extremum;  // m
  double final_displacement;  // m
};

// SDNV104 in Bullet (header): the shoe's centre starts at (0.5, 0.5); dx its displacement along x.
BulletRun run_bullet_sdnv104(double h, double end) {
  const double mass = 7000, k = 24000, mu = 0.3, normal_force = 70000, push = 200000;
  btTransform pose;
  pose.setIdentity();
  pose.setOrigin(btVector3(0.5, 0.5, 0.0));
  BulletWorld b(btVector3(0, 1, 0), btVector3(0.5, 0.5, 0.5), mass, pose, mu);
  b.box->setLinearFactor(btVector3(1, 1, 0));
  b.box->setAngularFactor(btVector3(0, 0, 1));
  const long steps = std::lround(end / h);
  double previous = 0.0, first_extremum = NAN;
  bool rising = true;
  const auto start = std::chrono::steady_clock::now();
  for (long s = 0; s < steps; ++s) {
    const double dx = b.box->getCenterOfMassPosition().x() - 0.5;
    b.box->applyCentralForce(btVector3(push - k * dx, -normal_force, 0.0));  // cleared by each step
    b.world.stepSimulation(h, 0, h);
    const double x = b.box->getCenterOfMassPosition().x() - 0.5;
    if (rising && x < previous && std::isnan(first_extremum)) first_extremum = previous;
    rising = x >= previous;
    previous = x;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {1e6 * seconds / steps, first_extremum, previous};
}

// incline-3d in Bullet: the plane's normal and the cube turned by the angle about y, the cube resting
// on it, gravity along −z. Returns the slide along the slope at the end (m) as first_extremum.
BulletRun run_bullet_incline(double h, double end) {
  const double mass = 10, angle = 20 * M_PI / 180, mu = 0.5, g = 9.81, size = 0.2;
  const btQuaternion turn(btVector3(0, 1, 0), angle);
  const btVector3 normal = btMatrix3x3(turn) * btVector3(0, 0, 1);
  btTransform pose(turn, 0.5 * size * normal);
  BulletWorld b(normal, btVector3(0.5 * size, 0.5 * size, 0.5 * size), mass, pose, mu);
  b.world.setGravity(btVector3(0, 0, -g));
  const btVector3 start_position = b.box->getCenterOfMassPosition();
  const btVector3 down_slope = btMatrix3x3(turn) * btVector3(1, 0, 0);
  const long steps = std::lround(end / h);
  const auto start = std::chrono::steady_clock::now();
  for (long s = 0; s < steps; ++s) b.world.stepSimulation(h, 0, h);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double slide = (b.box->getCenterOfMassPosition() - start_position).dot(down_slope);
  return {1e6 * seconds / steps, slide, slide};
}

void print_row(const char* what, const Spread& s) {
  std::printf("  %-28s %8.3f   %6.3f – %6.3f\n", what, s.median, s.min, s.max);
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const double end_scale = argc > 2 ? std::atof(argv[2]) : 1.0;
  const std::string root = CSIM_SOURCE_DIR "/scenes/";
  auto end_override = [&](double end) { return "time.end=" + std::to_string(end * end_scale); };

  std::printf("csim against Bullet %d.%02d (double precision), %d alternating repeats, one thread\n",
              btGetVersion() / 100, btGetVersion() % 100, repeats);
  std::printf("  %-28s %8s   %s\n", "run", "us/step", "min – max");

  {  // SDNV104
    const double h = 1e-5, end = 10.0 * end_scale;
    const auto scene = csim::load_scene(root + "sdnv104-rigid/scene.yaml", {"time.step=1e-5", end_override(10.0)});
    std::vector<double> csim_us, bullet_us, ratios;
    CsimRun c{};
    BulletRun b{};
    for (int r = 0; r < repeats; ++r) {
      c = run_csim(*scene);
      b = run_bullet_sdnv104(h, end);
      csim_us.push_back(c.us_per_step);
      bullet_us.push_back(b.us_per_step);
      ratios.push_back(c.us_per_step / b.us_per_step);
    }
    std::printf("sdnv104-rigid, h = 1e-5, %g s\n", end);
    print_row("csim", spread(csim_us));
    print_row("Bullet", spread(bullet_us));
    print_row("ratio csim / Bullet", spread(ratios));
    std::printf("  first extremum of dx (m): exact %.6f, csim %.6f, Bullet %.6f; Bullet's final dx %.4f\n",
                2 * (200000 - 0.3 * 70000) / 24000.0, c.first_extremum, b.first_extremum, b.final_displacement);
  }
  {  // incline-3d
    const double h = 1e-5, end = 10.0 * end_scale;
    const auto scene = csim::load_scene(root + "incline-3d/scene.yaml", {"time.step=1e-5", end_override(10.0)});
    std::vector<double> csim_us, bullet_us, ratios;
    BulletRun b{};
    for (int r = 0; r < repeats; ++r) {
      const CsimRun c = run_csim(*scene);
      b = run_bullet_incline(h, end);
      csim_us.push_back(c.us_per_step);
      bullet_us.push_back(b.us_per_step);
      ratios.push_back(c.us_per_step / b.us_per_step);
    }
    std::printf("incline-3d, h = 1e-5, %g s\n", end);
    print_row("csim", spread(csim_us));
    print_row("Bullet", spread(bullet_us));
    print_row("ratio csim / Bullet", spread(ratios));
    std::printf("  slide at the end (m): exact 0 (tan 20° < 0.5: it sticks), Bullet %.3e\n", b.first_extremum);
  }
  {  // sdnd100-a
    const auto scene = csim::load_scene(root + "sdnd100-a/scene.yaml", {"time.step=2e-6", end_override(0.3)});
    std::vector<double> csim_us;
    for (int r = 0; r < repeats; ++r) csim_us.push_back(run_csim(*scene).us_per_step);
    std::printf("sdnd100-a, h = 2e-6, %g s\n", 0.3 * end_scale);
    print_row("csim", spread(csim_us));
  }
  return 0;
}
