// Shared helpers of the simulation tests: materials, walls and small scenes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sim/contact_kernel.hpp"
#include "sim/scene_io.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim::testing {

// Restores the process's kernel choice when a test ends.
class KernelChoice {
 public:
  KernelChoice() { use_ = kernel::activeIsa(&isa_); }
  ~KernelChoice() { kernel::setActive(use_, isa_); }

 private:
  bool use_;
  kernel::Isa isa_;
};

// Returns a random unit vector (uniform on the sphere).
inline Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<Real> n;
  Vec3 v(n(rng), n(rng), n(rng));
  return v / v.norm();
}

// Returns a random orientation (uniform over rotations).
inline Quat randomQuat(std::mt19937_64& rng) {
  std::normal_distribution<Real> n;
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

// Returns checkpoint file bytes with the scene's part changed by edit and the checksum made
// anew: the reader's own checks see the change instead of the checksum catching it first.
template <class F>
std::string editCheckpoint(const std::string& file, F&& edit) {
  std::string scene = unsealCheckpoint(file);
  edit(scene);
  return sealCheckpoint(std::move(scene));
}

// Returns the error code words after DEMLAB of the Error f throws; fails if it does not throw.
template <class F>
std::vector<std::string> codeOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return {e.code().begin() + 1, e.code().end()};
  }
  ADD_FAILURE() << "no error thrown";
  return {};
}

// Sets the watchdog's options from one struct, through the generic option pair.
inline void setWatchdog(Simulation& s, const WatchdogOptions& o) {
  s.setOptions({{"watchdog", "on", o.enabled},
                {"watchdog", "overlap", o.overlap},
                {"watchdog", "placed", o.placed},
                {"watchdog", "energy", o.energy},
                {"watchdog", "speed", o.speed}});
}

// Returns the watchdog's options of s as one struct.
inline WatchdogOptions watchdogOf(const Simulation& s) {
  const auto get = [&](const char* n) { return s.option("watchdog", n); };
  return {std::get<bool>(get("on")), std::get<double>(get("overlap")),
          std::get<double>(get("placed")), std::get<double>(get("energy")),
          std::get<bool>(get("speed"))};
}

// Returns the vertical axis of a dim-dimensional scene (y in 2D, z in 3D).
inline int up(int d) {
  return d == 2 ? 1 : 2;
}

// Returns true if the next step of s runs the module named name.
inline bool hasModule(const Simulation& s, const std::string& name) {
  const auto m = s.listModules();
  return std::find(m.begin(), m.end(), name) != m.end();
}

inline MaterialDef material(double young, double restitution, double friction,
                            double density = 2500) {
  MaterialDef m;
  m.density = density;
  m.young = young;
  m.poisson = 0.3;
  m.restitution = restitution;
  m.friction = friction;
  return m;
}

inline WallDef plane(const Vec3d& point, const Vec3d& normal, const std::string& mat) {
  WallDef w;
  w.shape = WallShape::Plane;
  w.point = point;
  w.normal = normal;
  w.material = mat;
  return w;
}

inline ElementDef grain(const Vec3d& x, double r, const std::string& mat, const Vec3d& v = {}) {
  ElementDef g;
  g.position = x;
  g.radius = r;
  g.material = mat;
  g.velocity = v;
  return g;
}

// Drops a ball of radius 1 cm with spin onto a plane and into a resting ball (friction 0.4,
// restitution 0.5, 10 000 steps of 2e-5 s), the first ball replaced by an element of shape
// `shape` with `params` when shape is given; returns both elements' end states. A shape that
// is the ball in disguise must give the ball's run. The touch correction is off: it covers
// ball-ball and ball-wall contacts, not shapes'.
inline std::array<ElementState, 2> dropIntoBall(std::unique_ptr<Simulation> s,
                                                const std::string& shape = "",
                                                const std::vector<double>& params = {}) {
  s->setOption("touch", "on", false);
  s->addMaterial("glass", material(1e7, 0.5, 0.4));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
  s->addGravity({0, 0, -9.81});
  ElementDef a = grain({0, 0, 0.03}, 0.01, "glass", {0.2, 0, -0.3});
  a.angularVelocity = {3, 1, -2};
  if (!shape.empty()) {
    a.radius = 0;
    a.shape = shape;
    a.shapeParams = params;
  }
  const ElementId ia = s->addElement(a);
  const ElementId ib = s->addElement(grain({0.03, 0.002, 0.0099}, 0.01, "glass"));
  s->setTimeStep(2e-5);
  RunOptions o;
  o.steps = 10000;
  s->run(o);
  return {s->element(ia), s->element(ib)};
}

// Expects the end states of dropIntoBall for a shape (got) to be the ball's (want) within tol
// (angular velocities within 100 tol), and the ball struck to have moved.
inline void expectSamePath(const std::array<ElementState, 2>& got,
                           const std::array<ElementState, 2>& want, double tol) {
  for (int e = 0; e < 2; ++e) {
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(got[e].position[d], want[e].position[d], tol) << e << d;
      EXPECT_NEAR(got[e].velocity[d], want[e].velocity[d], tol) << e << d;
      EXPECT_NEAR(got[e].angularVelocity[d], want[e].angularVelocity[d], 100 * tol) << e << d;
    }
  }
  EXPECT_GT(std::abs(want[1].position[0] - 0.03), 1e-3);
}

// Expects element add of shape with each of the parameter lists to fail with {VALUE SHAPE} in a
// 3D scene, changing nothing.
inline void expectShapesRefused(const std::string& shape,
                                const std::vector<std::vector<double>>& bad) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.3, 0.5));
  for (const std::vector<double>& p : bad) {
    ElementDef e = grain({0, 0, 0}, 0, "glass");
    e.shape = shape;
    e.shapeParams = p;
    const uint64_t before = s->stateDigest();
    EXPECT_EQ(codeOf([&] { s->addElement(e); }), (std::vector<std::string>{"VALUE", "SHAPE"}));
    EXPECT_EQ(s->stateDigest(), before);
  }
}

// Adds the 2 D walls of the box [0, side]^D (planes facing inwards).
inline void addBox(Simulation& s, double side, const std::string& mat) {
  const int d = s.dim();
  for (int k = 0; k < d; ++k) {
    Vec3d n{0, 0, 0}, p{0, 0, 0};
    n[k] = 1;
    s.addWall(plane(p, n, mat));
    n[k] = -1;
    p[k] = side;
    s.addWall(plane(p, n, mat));
  }
}

// Returns defs for n non-overlapping grains of radius r on a jittered lattice inside the box
// [0, side]^D, with random velocities of magnitude up to vmax (seeded: reproducible).
inline std::vector<ElementDef> latticeGrains(int dim, int n, double r, double side, double vmax,
                                           const std::string& mat, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const double pitch = 2.2 * r;
  const int perAxis = static_cast<int>((side - 2 * r) / pitch);
  int room = 1;
  for (int a = 0; a < dim; ++a) room *= perAxis;
  EXPECT_LE(n, room) << "the lattice does not fit in the box";
  std::vector<ElementDef> out;
  for (int k = 0; k < n; ++k) {
    int c = k;
    Vec3d x{0, 0, 0}, v{0, 0, 0};
    for (int a = 0; a < dim; ++a) {
      x[a] = 1.2 * r + pitch * (c % perAxis) + 0.05 * r * u(rng);
      c /= perAxis;
      v[a] = vmax * u(rng);
    }
    out.push_back(grain(x, r, mat, v));
  }
  return out;
}

// What a block did on a slope: how far it moved down the slope, its acceleration there and its
// last state.
struct InclineRun {
  double moved = 0, acceleration = 0;
  ElementState end;
};

// Places element e (material "glass", Young 1e7, restitution 0.3, friction mu) on a floor under
// gravity g0 tilted by theta along x, at the automatic step over stepDivisor; lets it settle for
// settle seconds and returns what it does in the next measure seconds.
inline InclineRun runIncline(ElementDef e, double theta, double mu, double settle, double measure,
                             double stepDivisor = 1) {
  const double g0 = 9.81;
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.3, mu));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
  s->addGravity({g0 * std::sin(theta), 0, -g0 * std::cos(theta)});
  e.material = "glass";
  const ElementId id = s->addElement(e);
  s->setTimeStep(s->timeStep() / stepDivisor);
  const auto runFor = [&](double t) {
    RunOptions o;
    o.steps = static_cast<uint64_t>(std::ceil(t / s->timeStep()));
    s->run(o);
  };
  runFor(settle);
  const ElementState a = s->element(id);
  const double t0 = s->time();
  runFor(measure);
  InclineRun r;
  r.end = s->element(id);
  const double T = s->time() - t0;
  r.moved = r.end.position[0] - a.position[0];
  r.acceleration = 2 * (r.moved - a.velocity[0] * T) / (T * T);
  return r;
}

}  // namespace demlab::sim::testing
