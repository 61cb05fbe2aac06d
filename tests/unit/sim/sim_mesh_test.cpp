// Triangle-mesh walls: the mesh's merging and grid against brute force, the nearest point of a
// triangle against dense sampling, a sphere's contacts with flat, ridged and valleyed meshes
// against the planes they are made of (one contact per surface, none doubled where triangles
// meet), and whole runs against the same scene with plane walls.
#include <cmath>
#include <random>

#include "physics/mesh_contact.hpp"
#include "physics/narrow_phase.hpp"
#include "physics/triangle_mesh.hpp"
#include "sim/simulation_manager.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_mesh_test {

using physics::MeshShape;
using physics::TriangleMesh;
using testing::grain;
using testing::material;
using testing::plane;
using testing::randomQuat;

using Tris = std::vector<std::array<double, 9>>;

std::array<double, 9> tri(const Vec3& a, const Vec3& b, const Vec3& c) {
  return {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.x(), c.y(), c.z()};
}

// An n x n grid of squares over [-h, h]^2 at z = 0, each cut in two along alternating diagonals.
Tris flatGrid(int n, double h) {
  Tris t;
  const auto at = [&](int i, int j) { return Vec3(-h + 2 * h * i / n, -h + 2 * h * j / n, 0); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if ((i + j) % 2 == 0) {
        t.push_back(tri(at(i, j), at(i + 1, j), at(i + 1, j + 1)));
        t.push_back(tri(at(i, j), at(i + 1, j + 1), at(i, j + 1)));
      } else {
        t.push_back(tri(at(i, j), at(i + 1, j), at(i, j + 1)));
        t.push_back(tri(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)));
      }
    }
  }
  return t;
}

MeshShape<3> placed(const Tris& t, const Quat& q = Quat::Identity(), const Vec3& x = Vec3::Zero()) {
  MeshShape<3> m;
  m.mesh = std::make_shared<const TriangleMesh>(TriangleMesh::build(t, "test"));
  m.rotation = q.toRotationMatrix();
  m.offset = x;
  return m;
}

TEST(SimMesh, CornersMergeAndTheGridFindsEveryNearTriangle) {
  const TriangleMesh grid = TriangleMesh::build(flatGrid(8, 1), "grid");
  EXPECT_EQ(grid.vertices.size(), 81u);
  EXPECT_EQ(grid.triangles.size(), 128u);
  Tris withFlat = flatGrid(2, 1);
  withFlat.push_back(tri(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 2, 0)));  // no area: dropped
  EXPECT_EQ(TriangleMesh::build(withFlat, "x").triangles.size(), 8u);
  EXPECT_THROW(TriangleMesh::build({tri(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 2, 0))}, "x"), Error);
  // Random triangles of mixed sizes: near() returns every triangle whose bounds come within
  // reach, against a scan of all.
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1), s(0.001, 0.5);
  Tris t;
  for (int k = 0; k < 400; ++k) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const double size = s(rng) * s(rng) * 4;
    t.push_back(tri(c, Vec3(c + size * testing::randomUnit(rng)), Vec3(c + size * testing::randomUnit(rng))));
  }
  const TriangleMesh m = TriangleMesh::build(t, "random");
  std::vector<uint32_t> got;
  for (int k = 0; k < 500; ++k) {
    const Vec3 p(1.2 * u(rng), 1.2 * u(rng), 1.2 * u(rng));
    const double reach = 0.05 * s(rng);
    m.near(p, reach, got);
    for (uint32_t j = 0; j < m.triangles.size(); ++j) {
      Vec3 lo = m.vertices[m.triangles[j][0]], hi = lo;
      for (uint32_t v : m.triangles[j]) lo = lo.cwiseMin(m.vertices[v]), hi = hi.cwiseMax(m.vertices[v]);
      const bool close = ((p.array() + reach) >= lo.array()).all() && ((p.array() - reach) <= hi.array()).all();
      if (close) {
        EXPECT_TRUE(std::binary_search(got.begin(), got.end(), j)) << k << " " << j;
      }
    }
  }
}

TEST(SimMesh, NearestPointOfATriangleAgreesWithSampling) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 200; ++k) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    const physics::TrianglePoint got = physics::nearestOnTriangle(p, a, b, c);
    double best = 1e300;
    const int n = 120;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        best = std::min(best, (p - q).norm());
      }
    }
    const double d = (p - got.point).norm();
    EXPECT_LE(d, best + 1e-12) << k;
    EXPECT_GT(d, best - 0.03) << k;  // the sampling's spacing
  }
}

// A sphere over a flat mesh of many triangles meets it as the plane: one contact wherever it
// is (over a triangle's inside, an edge shared by two, a corner shared by six), the plane's
// overlap and normal.
TEST(SimMesh, OneContactOnAFlatMeshWhereverItLies) {
  std::mt19937_64 rng(12);
  const Quat q = randomQuat(rng);
  const Vec3 x(0.3, -0.2, 0.5);
  const MeshShape<3> m = placed(flatGrid(6, 0.1), q, x);
  const Vec3 n = q * Vec3::UnitZ();
  std::uniform_real_distribution<double> u(-0.08, 0.08), dep(0.0001, 0.002);
  physics::MeshContact<3> c[16];
  for (int k = 0; k < 300; ++k) {
    // Every third on a grid corner or edge exactly.
    Vec3 local(u(rng), u(rng), 0);
    if (k % 3 == 0) local = Vec3(std::round(local.x() * 30) / 30, std::round(local.y() * 30) / 30, 0);
    if (k % 3 == 1) local.x() = std::round(local.x() * 30) / 30;
    const double r = 0.01, depth = dep(rng);
    const int side = k % 2 == 0 ? 1 : -1;  // two-sided
    const Vec3 centre = x + q * local + side * (r - depth) * n;
    const int count = physics::sphereMeshContacts<3>({centre, r}, m, c, 16);
    ASSERT_EQ(count, 1) << k << " at " << local.transpose();
    EXPECT_NEAR(c[0].g.overlap, depth, 1e-12) << k;
    EXPECT_LT((c[0].g.normal + side * n).norm(), 1e-9) << k;
  }
}

// Two faces meeting at an edge: over a ridge (convex) a sphere touching the edge only gets one
// contact, along the line from its centre to the edge; in a valley (concave) one touching both
// faces gets two, each its plane's.
TEST(SimMesh, RidgesGiveOneContactAndValleysTwo) {
  const double a = 0.4;  // the faces' slope angle
  const Vec3 d1(std::cos(a), 0, std::sin(a)), d2(-std::cos(a), 0, std::sin(a));
  Tris valley, ridge;
  for (const Vec3& d : {d1, d2}) {
    const Vec3 far = 0.1 * d;
    // Each face split in four triangles sharing its edges.
    for (int k = 0; k < 2; ++k) {
      const double y0 = -0.1 + 0.1 * k, y1 = y0 + 0.1;
      valley.push_back(tri(Vec3(0, y0, 0), Vec3(far.x(), y0, far.z()), Vec3(far.x(), y1, far.z())));
      valley.push_back(tri(Vec3(0, y0, 0), Vec3(far.x(), y1, far.z()), Vec3(0, y1, 0)));
      ridge.push_back(tri(Vec3(0, y0, 0), Vec3(far.x(), y0, -far.z()), Vec3(far.x(), y1, -far.z())));
      ridge.push_back(tri(Vec3(0, y0, 0), Vec3(far.x(), y1, -far.z()), Vec3(0, y1, 0)));
    }
  }
  physics::MeshContact<3> c[16];
  const double r = 0.01;
  // Valley: a sphere on the axis touching both faces.
  const Vec3 up(0, 0, 1);
  const double h = (r - 0.001) / std::cos(a);  // each face's distance r - 1 mm
  ASSERT_EQ(physics::sphereMeshContacts<3>({Vec3(0, 0.003, h), r}, placed(valley), c, 16), 2);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(c[k].g.overlap, 0.001, 1e-12);
  // Ridge: a sphere above the edge touching only it.
  ASSERT_EQ(physics::sphereMeshContacts<3>({Vec3(0, 0.05, r - 0.001), r}, placed(ridge), c, 16), 1);
  EXPECT_NEAR(c[0].g.overlap, 0.001, 1e-12);
  EXPECT_LT((c[0].g.normal + up).norm(), 1e-12);
  // Over the ridge's shared corner (y = 0, where four triangles meet): still one.
  ASSERT_EQ(physics::sphereMeshContacts<3>({Vec3(0, 0, r - 0.002), r}, placed(ridge), c, 16), 1);
}

// Adds a floor at z = 0 of material glass: a plane, or a mesh of 800 triangles.
void addFloor(Simulation& s, bool mesh) {
  if (!mesh) {
    s.addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    return;
  }
  WallDef w;
  w.shape = WallShape::Mesh;
  w.mesh = std::make_shared<const TriangleMesh>(TriangleMesh::build(flatGrid(20, 0.2), "floor"));
  w.material = "glass";
  s.addWall(w);
}

// A ball rolling and bouncing across a floor of 800 triangles follows the plane floor's path: no
// doubled force where it crosses their edges and corners. (The touch correction, which covers
// the plane's contacts and not a mesh's, is off in both.)
TEST(SimMesh, ABallCrossesAMeshFloorAsAPlane) {
  std::array<ElementState, 2> end;
  for (int run = 0; run < 2; ++run) {
    auto s = makeSimulation(3);
    s->setOption("touch", "on", false);
    s->addMaterial("glass", material(1e7, 0.5, 0.4));
    addFloor(*s, run == 1);
    s->addGravity({0, 0, -9.81});
    const ElementId id = s->addElement(grain({-0.1, -0.05, 0.03}, 0.01, "glass", {0.5, 0.25, 0}));
    s->runTime(0.3);
    end[run] = s->element(id);
  }
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(end[1].position[d], end[0].position[d], 1e-9) << d;
    EXPECT_NEAR(end[1].velocity[d], end[0].velocity[d], 1e-7) << d;
    EXPECT_NEAR(end[1].angularVelocity[d], end[0].angularVelocity[d], 1e-5) << d;
  }
  EXPECT_GT(end[0].position[0], 0.0);  // it has crossed many triangles
}

// An ellipsoid and a cube (polyhedron) dropped tilted on a floor of 800 triangles land and
// settle as on a plane: the same position and velocity after 0.4 s.
TEST(SimMesh, ShapesRestOnAMeshFloorAsOnAPlane) {
  for (const std::string shape : {"superquadric", "polyhedron", "levelset"}) {
    std::array<ElementState, 2> end;
    for (int run = 0; run < 2; ++run) {
      auto s = makeSimulation(3);
      MaterialDef mat = material(1e7, 0.3, 0.5);
      mat.rollingFriction = 0.05;
      s->addMaterial("glass", mat);
      addFloor(*s, run == 1);
      s->addGravity({0, 0, -9.81});
      ElementDef e = grain({0.013, -0.021, 0.04}, 0, "glass");
      e.shape = shape;
      if (shape == "superquadric") {
        e.shapeParams = {0.02, 0.013, 0.008, 2, 2};
      } else if (shape == "polyhedron") {
        e.shapeParams = {-0.01, -0.01, -0.01, 0.01, -0.01, -0.01, -0.01, 0.01, -0.01, 0.01, 0.01, -0.01,
                         -0.01, -0.01, 0.01, 0.01, -0.01, 0.01, -0.01, 0.01, 0.01, 0.01, 0.01, 0.01};
      } else {
        // The same cube as a level set, from its max-norm function on a grid of 4 mm.
        const Real h = 0.004;
        std::vector<double> values;
        for (int k = 0; k < 9; ++k)
          for (int j = 0; j < 9; ++j)
            for (int i = 0; i < 9; ++i) values.push_back(h * std::max({std::abs(i - 4), std::abs(j - 4), std::abs(k - 4)}) - 0.01);
        e.shapeParams = levelSetFromValues<3>(h, {9, 9, 9}, Vec3::Constant(-4 * h), values);
      }
      e.orientation = {0.99, 0.1, 0.05, 0.02};
      const ElementId id = s->addElement(e);
      // A level set's face bears on its 5 x 5 nodes: a stiffer contact, a shorter step.
      if (shape == "levelset") s->setTimeStep(s->timeStep() / 5);
      s->runTime(0.4);
      end[run] = s->element(id);
    }
    // Down on the floor (the cube on a face; the ellipsoid still rocking, on its flattest side).
    for (int run = 0; run < 2; ++run) {
      EXPECT_LT(end[run].position[2], shape == "superquadric" ? 0.01 : 0.0102) << shape << run;
    }
    // The ellipsoid still rocks, and a mesh keys its contact springs by triangle, so they start
    // again where a contact point crosses an edge, as a plane's never do: micrometres apart
    // (the springs follow the drift's displacement, which damps no rocking; physics/tangential.hpp).
    const bool rocking = shape == "superquadric";
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(end[1].position[d], end[0].position[d], rocking ? 2e-5 : 1e-6) << shape << d;
      EXPECT_NEAR(end[1].velocity[d], end[0].velocity[d], rocking ? 1e-3 : 1e-4) << shape << d;
    }
  }
}

}  // namespace sim_mesh_test
}  // namespace demlab::sim
