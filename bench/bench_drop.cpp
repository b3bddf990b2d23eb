// Bodies dropped into a box, csim against Bullet 3.24 (Debian's libbullet-dev, double precision): the
// physics-engine benchmark of many bodies (run by hand: build/bench/bench_drop spheres|cubes N [steps]
// [repeats] [--scene FILE]); with --scene it writes csim's scene file of these bodies and stops.
//
// The bodies: N spheres of radius 0.05 m or cubes of side 0.1 m, 1 kg each, on a grid of ⌈∛N⌉ a side at a
// spacing of 2.5 radii (spheres) or 1.5 sides (cubes), the lowest layer just above the floor, inside a
// box of four walls whose inner sides are half a spacing from the outer bodies; each body moved across by
// up to 0.2 radii (spheres) or 0.1 sides (cubes), seeded, so that the columns topple into a pile (no two
// bodies overlap at the start: neighbours stay 2.1 radii apart, turned cubes 0.005 m), and
// each cube turned about z by a different small angle (0.05 (k mod 7) rad), so that no two faces meet
// square. Released at rest;
// gravity 9.81 m/s², Coulomb μ = 0.5 on every contact, e = 0, h = 1e-3.
// csim: Moreau–Jean, θ = ½, the contact solver's tolerance 1e-6 (issue targets), the scene written as a
// generator would (one entry per body, group laws). Bullet: btDiscreteDynamicsWorld with 100 solver
// iterations, two friction directions, no sleeping, friction √0.5 on every body and wall (Bullet
// multiplies the two sides' values), a collision margin of 1 mm on the cubes (its default, 4 cm, would
// round the 0.1 m cubes' corners), split impulse on (its default).
//
// Each run is a child process (fork), so that its peak resident memory (wait4's ru_maxrss) is its own;
// the engines alternate over the repeats. Printed per engine: µs per step (median, min–max), peak memory
// (median) beside that of a child that only loads the program, and at the end of the run: the pile's top
// (m), the deepest overlap between two bodies or a body and the box (m), the kinetic energy per body
// (J); csim also its deepest overlap over the whole run, its contact solves that stopped above the
// tolerance, its largest final residual and its energy balance (the worst residual of the discrete
// balance over the run, and what the contacts dissipated). Ratios csim / Bullet from the same repeats.
#include "bench/spread.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <btBulletDynamicsCommon.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr double kGravity = 9.81, kMu = 0.5, kStep = 1e-3, kMass = 1.0;
constexpr double kRadius = 0.05, kSide = 0.1;

struct Layout {
  bool cubes = false;
  int count = 0, per_side = 0;
  double spacing = 0.0, size = 0.0;  // m; size: the radius or the half side
  double inner_half_width = 0.0;     // m, from the box's centre to a wall
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> yaw;  // rad
};

Layout layout(bool cubes, int count) {
  Layout l;
  l.cubes = cubes;
  l.count = count;
  l.per_side = static_cast<int>(std::ceil(std::cbrt(static_cast<double>(count)) - 1e-9));
  l.size = cubes ? 0.5 * kSide : kRadius;
  l.spacing = cubes ? 1.5 * kSide : 2.5 * kRadius;
  l.inner_half_width = 0.5 * l.per_side * l.spacing;
  std::mt19937 random(1);
  std::uniform_real_distribution<double> across(-1.0, 1.0);
  const double jitter = cubes ? 0.1 * kSide : 0.2 * kRadius;
  for (int k = 0; k < count; ++k) {
    const int i = k % l.per_side, j = (k / l.per_side) % l.per_side, layer = k / (l.per_side * l.per_side);
    l.positions.emplace_back((i + 0.5) * l.spacing - l.inner_half_width, (j + 0.5) * l.spacing - l.inner_half_width,
                             l.size * 1.01 + layer * l.spacing);
    l.positions.back().x() += jitter * across(random);
    l.positions.back().y() += jitter * across(random);
    l.yaw.push_back(cubes ? 0.05 * (k % 7) : 0.0);
  }
  return l;
}

std::string csim_scene_text(const Layout& l, int steps) {
  std::string text = "dimension: 3\ngravity: [0, 0, -9.81]\nbodies:\n";
  char line[512];
  for (int k = 0; k < l.count; ++k) {
    const Eigen::Vector3d& p = l.positions[k];
    const std::string shape = l.cubes ? "{type: box, size: [0.1, 0.1, 0.1]}" : "{type: sphere, radius: 0.05}";
    std::snprintf(line, sizeof line,
                  "  b%d: {type: rigid, mass: 1, position: [%.17g, %.17g, %.17g], angle: %.17g, axis: [0, 0, 1], "
                  "shapes: {s: %s}, group: pile}\n",
                  k, p.x(), p.y(), p.z(), l.yaw[k] * 180.0 / M_PI, shape.c_str());
    text += line;
  }
  const double w = l.inner_half_width;
  std::snprintf(line, sizeof line,
                "  box: {type: fixed, shapes: {floor: {type: halfspace, normal: [0, 0, 1], offset: 0},\n"
                "    west: {type: halfspace, normal: [1, 0, 0], offset: %.17g},\n"
                "    east: {type: halfspace, normal: [-1, 0, 0], offset: %.17g},\n"
                "    south: {type: halfspace, normal: [0, 1, 0], offset: %.17g},\n"
                "    north: {type: halfspace, normal: [0, -1, 0], offset: %.17g}}}\n",
                -w, -w, -w, -w);
  text += line;
  std::snprintf(line, sizeof line,
                "contacts:\n  pile: {between: [pile, pile], mu: %g}\n  walls: {between: [box, pile], mu: %g}\n"
                "time: {end: %.17g, step: %g}\nintegrator: {type: moreau-jean, theta: 0.5}\n"
                "contact_solver: {tolerance: 1e-6, max_iterations: 20000}\noutput: {rate: 1}\n",
                kMu, kMu, steps * kStep, kStep);
  return text + line;
}

// What a run measured (sent from the child to the parent as raw bytes).
struct Outcome {
  double us_per_step = NAN;
  double top = NAN;            // m, the highest point of any body at the end
  double overlap_end = NAN;    // m, the deepest overlap at the end
  double overlap_run = NAN;    // m, csim: over the run
  double kinetic_per_body = NAN;  // J
  long not_converged = -1;     // csim: contact solves above the tolerance
  double max_residual = NAN;   // csim
  double energy_residual = NAN;  // J, csim: the worst |energy balance| over the run (state.h)
  double dissipated = NAN;       // J, csim: by the contacts
  bool ok = false;
};

double cube_top(const Eigen::Isometry3d& pose) {
  double top = -INFINITY;
  for (int v = 0; v < 8; ++v) {
    const Eigen::Vector3d corner(v & 1 ? 0.05 : -0.05, v & 2 ? 0.05 : -0.05, v & 4 ? 0.05 : -0.05);
    top = std::max(top, (pose * corner).z());
  }
  return top;
}

Outcome run_csim(const Layout& l, int steps) {
  const std::string file = "/tmp/bench_drop_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << csim_scene_text(l, steps);
  const std::unique_ptr<csim::Scene> scene = csim::load_scene(file, {});
  std::remove(file.c_str());
  const csim::RunReport report = csim::run_scene(*scene, {});
  Outcome o;
  const csim::State& s = report.state;
  o.us_per_step = 1e6 * report.wall_time / static_cast<double>(s.counters.steps);
  o.top = -INFINITY;
  for (const csim::BodyInstance& b : scene->world.bodies) {
    if (b.body->fixed()) continue;
    const Eigen::Isometry3d pose = b.body->pose(b.positions(s.q));
    o.top = std::max(o.top, l.cubes ? cube_top(pose) : pose.translation().z() + kRadius);
  }
  o.overlap_end = 0.0;
  for (const csim::ActiveContact& c : s.contacts) o.overlap_end = std::max(o.overlap_end, -c.point.gap);
  o.overlap_run = s.counters.deepest_penetration;
  o.kinetic_per_body = s.energy.kinetic / l.count;
  o.not_converged = s.counters.not_converged;
  o.max_residual = s.counters.max_residual;
  o.energy_residual = s.energy.max_abs_residual;
  o.dissipated = s.energy.contact_dissipation;
  o.ok = !report.failure;
  return o;
}

Outcome run_bullet(const Layout& l, int steps) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, 0, -kGravity));
  world.getSolverInfo().m_numIterations = 100;
  world.getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
  const double friction = std::sqrt(kMu);
  const double w = l.inner_half_width;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  auto add_wall = [&](const btVector3& normal, double offset) {
    shapes.push_back(std::make_unique<btStaticPlaneShape>(normal, offset));
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shapes.back().get());
    info.m_friction = friction;
    info.m_restitution = 0.0;
    bodies.push_back(std::make_unique<btRigidBody>(info));
    world.addRigidBody(bodies.back().get());
  };
  add_wall({0, 0, 1}, 0.0);
  add_wall({1, 0, 0}, -w);
  add_wall({-1, 0, 0}, -w);
  add_wall({0, 1, 0}, -w);
  add_wall({0, -1, 0}, -w);
  std::unique_ptr<btCollisionShape> body_shape;
  if (l.cubes) {
    body_shape = std::make_unique<btBoxShape>(btVector3(0.05, 0.05, 0.05));
    body_shape->setMargin(1e-3);
  } else {
    body_shape = std::make_unique<btSphereShape>(kRadius);
  }
  btVector3 inertia;
  body_shape->calculateLocalInertia(kMass, inertia);
  std::vector<btRigidBody*> pile;
  for (int k = 0; k < l.count; ++k) {
    btRigidBody::btRigidBodyConstructionInfo info(kMass, nullptr, body_shape.get(), inertia);
    const Eigen::Vector3d& p = l.positions[k];
    info.m_startWorldTransform = btTransform(btQuaternion(btVector3(0, 0, 1), l.yaw[k]), btVector3(p.x(), p.y(), p.z()));
    info.m_friction = friction;
    info.m_restitution = 0.0;
    bodies.push_back(std::make_unique<btRigidBody>(info));
    bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(bodies.back().get());
    pile.push_back(bodies.back().get());
  }
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) world.stepSimulation(kStep, 0, kStep);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Outcome o;
  o.us_per_step = 1e6 * seconds / steps;
  o.top = -INFINITY;
  double kinetic = 0.0;
  for (btRigidBody* b : pile) {
    const btTransform& t = b->getWorldTransform();
    if (l.cubes) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      const btMatrix3x3& R = t.getBasis();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) pose.linear()(r, c) = R[r][c];
      pose.translation() << t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z();
      o.top = std::max(o.top, cube_top(pose));
    } else {
      o.top = std::max(o.top, static_cast<double>(t.getOrigin().z()) + kRadius);
    }
    const btVector3 v = b->getLinearVelocity(), omega = b->getAngularVelocity();
    kinetic += 0.5 * kMass * v.length2() + 0.5 * omega.dot(b->getInvInertiaTensorWorld().inverse() * omega);
  }
  o.kinetic_per_body = kinetic / l.count;
  o.overlap_end = 0.0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    for (int c = 0; c < manifold->getNumContacts(); ++c)
      o.overlap_end = std::max(o.overlap_end, -static_cast<double>(manifold->getContactPoint(c).getDistance()));
  }
  o.ok = true;
  for (auto& b : bodies) world.removeRigidBody(b.get());
  return o;
}

struct Child {
  Outcome outcome;
  double peak_mb = NAN;
};

// Runs `what` in a child process: its outcome and its peak resident memory.
template <typename Run>
Child in_child(Run what) {
  int pipe_ends[2];
  if (pipe(pipe_ends) != 0) std::abort();
  const pid_t pid = fork();
  if (pid == 0) {
    close(pipe_ends[0]);
    Outcome o;
    try {
      o = what();
    } catch (const std::exception& error) {
      std::fprintf(stderr, "run failed: %s\n", error.what());
    }
    if (write(pipe_ends[1], &o, sizeof o) != static_cast<ssize_t>(sizeof o)) _exit(1);
    _exit(0);
  }
  close(pipe_ends[1]);
  Child child;
  if (read(pipe_ends[0], &child.outcome, sizeof child.outcome) != static_cast<ssize_t>(sizeof child.outcome))
    child.outcome.ok = false;
  close(pipe_ends[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  child.peak_mb = usage.ru_maxrss / 1024.0;  // kB on Linux
  return child;
}

using csim::bench::Spread;
using csim::bench::spread;

}  // namespace

int main(int argc, char** argv) {
  const std::string kind = argc > 1 ? argv[1] : "cubes";
  if (kind != "cubes" && kind != "spheres") {
    std::printf("usage: bench_drop spheres|cubes N [steps] [repeats]\n");
    return 2;
  }
  const int count = argc > 2 ? std::max(1, std::atoi(argv[2])) : 27;
  const int steps = argc > 3 ? std::max(1, std::atoi(argv[3])) : 1000;
  const int repeats = argc > 4 ? std::max(1, std::atoi(argv[4])) : 3;
  const Layout l = layout(kind == "cubes", count);
  if (argc > 6 && std::string(argv[5]) == "--scene") {
    std::ofstream(argv[6]) << csim_scene_text(l, steps);
    return 0;
  }

  std::vector<Child> csim_runs, bullet_runs;
  for (int r = 0; r < repeats; ++r) {
    csim_runs.push_back(in_child([&] { return run_csim(l, steps); }));
    bullet_runs.push_back(in_child([&] { return run_bullet(l, steps); }));
  }
  const Child baseline = in_child([] { Outcome o; o.ok = true; return o; });

  std::printf("%d %s dropped into a box, %d steps of %g s, %d alternating repeats (Bullet %d.%02d, double)\n",
              count, kind.c_str(), steps, kStep, repeats, btGetVersion() / 100, btGetVersion() % 100);
  std::printf("  %-8s %10s %19s %9s %9s %11s %11s %11s\n", "engine", "us/step", "min - max", "peak MB",
              "top m", "overlap m", "run overlap", "KE/body J");
  std::vector<double> ratios, memory_ratios;
  for (int e = 0; e < 2; ++e) {
    const std::vector<Child>& runs = e == 0 ? csim_runs : bullet_runs;
    std::vector<double> us, mb;
    for (const Child& c : runs) {
      us.push_back(c.outcome.us_per_step);
      mb.push_back(c.peak_mb);
    }
    const Spread t = spread(us), m = spread(mb);
    const Outcome& last = runs.back().outcome;
    std::printf("  %-8s %10.1f %9.1f - %8.1f %9.1f %9.4f %11.2e %11.2e %11.2e%s\n", e == 0 ? "csim" : "Bullet",
                t.median, t.min, t.max, m.median, last.top, last.overlap_end, last.overlap_run,
                last.kinetic_per_body, last.ok ? "" : "  (run failed)");
  }
  for (int r = 0; r < repeats; ++r) {
    ratios.push_back(csim_runs[r].outcome.us_per_step / bullet_runs[r].outcome.us_per_step);
    memory_ratios.push_back(csim_runs[r].peak_mb / bullet_runs[r].peak_mb);
  }
  const Spread ratio = spread(ratios), memory = spread(memory_ratios);
  std::printf("  ratio csim / Bullet: step %.2f (%.2f - %.2f), peak memory %.2f (a child that only loads: %.1f MB)\n",
              ratio.median, ratio.min, ratio.max, memory.median, baseline.peak_mb);
  const Outcome& c = csim_runs.back().outcome;
  std::printf("  csim: %ld contact solves above the tolerance 1e-6, largest final residual %.2e; top csim - "
              "Bullet %.4f m\n",
              c.not_converged, c.max_residual, c.top - bullet_runs.back().outcome.top);
  std::printf("  csim's energy balance: worst residual %.2e J over the run, %.4g J dissipated by the contacts\n",
              c.energy_residual, c.dissipated);
  return 0;
}
