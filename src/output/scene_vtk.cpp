#include "output/scene_vtk.hpp"
#include "core/interrupt.hpp"
#include "mpi/communicator.hpp"
#include "physics/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace demlab::output {

namespace {

using io::VtkArray;
using sim::ElementId;
using sim::Vec3d;
using sim::WallId;
using io::VtkPolyData;

// Segments of a drum's circle: its facets differ from the true circle by 0.1% of the radius.
constexpr int kDrumSegments = 72;

Vec3d add(const Vec3d& a, const Vec3d& b, double s = 1) {
  return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d unit(const Vec3d& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? Vec3d{a[0] / n, a[1] / n, a[2] / n} : Vec3d{0, 0, 0};
}
// Returns a unit vector perpendicular to unit vector n.
Vec3d perpendicular(const Vec3d& n) {
  const Vec3d other = std::abs(n[0]) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  return unit(cross(n, other));
}

VtkArray timeArray(const char* name, double v) { return {name, 1, std::vector<double>{v}}; }

// Adds the scene's time and step count as field data (ParaView shows TIME).
void stamp(const sim::Simulation& s, VtkPolyData& d) {
  d.fieldData.push_back(timeArray("TIME", s.time()));
  d.fieldData.push_back({"STEP", 1, std::vector<int64_t>{int64_t(s.stepCount())}});
}

// Collects wall surfaces: polygons (3D) or lines (2D) over shared points, with the wall each
// cell belongs to.
struct WallMesh {
  VtkPolyData d;
  std::vector<size_t> wallOfCell;

  int64_t point(const Vec3d& p) {
    d.points.insert(d.points.end(), p.begin(), p.end());
    return int64_t(d.points.size() / 3 - 1);
  }
  void polygon(const std::vector<Vec3d>& corners, size_t wall) {
    for (const Vec3d& c : corners) d.polyConnectivity.push_back(point(c));
    d.polyOffsets.push_back(int64_t(d.polyConnectivity.size()));
    wallOfCell.push_back(wall);
  }
  // Adds the closed or open polyline through corners as lines.
  void polyline(const std::vector<Vec3d>& corners, bool closed, size_t wall) {
    std::vector<int64_t> ids;
    for (const Vec3d& c : corners) ids.push_back(point(c));
    const size_t n = ids.size(), segments = closed ? n : n - 1;
    for (size_t k = 0; k < segments; ++k) {
      d.lines.push_back(ids[k]);
      d.lines.push_back(ids[(k + 1) % n]);
      wallOfCell.push_back(wall);
    }
  }
};

// Returns the corners, in turn, of the rectangle about c spanned by hu along u and hv along v.
std::vector<Vec3d> rectangle(const Vec3d& c, const Vec3d& u, double hu, const Vec3d& v, double hv) {
  return {add(add(c, u, -hu), v, -hv), add(add(c, u, hu), v, -hv), add(add(c, u, hu), v, hv),
          add(add(c, u, -hu), v, hv)};
}

// Returns the half size of the square or segment drawn for an infinite plane: the scene's
// bounds' half diagonal, widened a little so the plane shows beyond the elements.
double planeHalfSize(const std::array<Vec3d, 2>& b) {
  const double d = std::sqrt(dot(add(b[1], b[0], -1), add(b[1], b[0], -1)));
  return d > 0 ? 0.6 * d : 0.5;
}

void meshWall(const sim::WallState& w, int dim, const std::array<Vec3d, 2>& bounds, size_t k,
              WallMesh& m) {
  using sim::WallShape;
  const Vec3d c = w.centre;
  if (dim == 2) {
    switch (w.shape) {
      case WallShape::Plane: {
        const Vec3d mid = {0.5 * (bounds[0][0] + bounds[1][0]), 0.5 * (bounds[0][1] + bounds[1][1]),
                           0};
        const Vec3d along = {-w.normal[1], w.normal[0], 0};
        const Vec3d foot = add(mid, along, dot(add(c, mid, -1), along));
        const Vec3d base = add(foot, w.normal, dot(add(c, foot, -1), w.normal));
        const double h = planeHalfSize(bounds);
        m.polyline({add(base, along, -h), add(base, along, h)}, false, k);
        break;
      }
      case WallShape::Finite:
        if (w.hole > 0) {  // a slot: the two segments either side of the gap
          m.polyline({add(c, w.axes[0], -w.halfExtents[0]), add(c, w.axes[0], -w.hole)}, false, k);
          m.polyline({add(c, w.axes[0], w.hole), add(c, w.axes[0], w.halfExtents[0])}, false, k);
          break;
        }
        m.polyline({add(c, w.axes[0], -w.halfExtents[0]), add(c, w.axes[0], w.halfExtents[0])},
                   false, k);
        break;
      case WallShape::Box: {
        m.polyline(rectangle(c, w.axes[0], w.halfExtents[0], w.axes[1], w.halfExtents[1]), true, k);
        break;
      }
      case WallShape::Drum: {
        std::vector<Vec3d> ring;
        for (int j = 0; j < kDrumSegments; ++j) {
          const double t = 2 * M_PI * j / kDrumSegments;
          ring.push_back({c[0] + w.radius * std::cos(t), c[1] + w.radius * std::sin(t), 0});
        }
        m.polyline(ring, true, k);
        break;
      }
      case WallShape::Mesh:
        break;  // 3D only
    }
    return;
  }
  switch (w.shape) {
    case WallShape::Plane: {
      const Vec3d mid = {0.5 * (bounds[0][0] + bounds[1][0]), 0.5 * (bounds[0][1] + bounds[1][1]),
                         0.5 * (bounds[0][2] + bounds[1][2])};
      const Vec3d base = add(mid, w.normal, dot(add(c, mid, -1), w.normal));
      const Vec3d u = perpendicular(w.normal), v = cross(w.normal, u);
      const double h = planeHalfSize(bounds);
      m.polygon(rectangle(base, u, h, v, h), k);
      break;
    }
    case WallShape::Finite: {
      if (w.hole > 0) {
        // An orifice plate: quads between the hole's rim and the edges, along rays from the
        // centre (a corner between two rays is cut off by less than their spacing).
        const int n = kDrumSegments;
        auto ray = [&](int j, bool rim) {
          const double t = 2 * M_PI * j / n, cu = std::cos(t), sv = std::sin(t);
          const double reach = std::min(cu != 0 ? w.halfExtents[0] / std::abs(cu) : 1e300,
                                        sv != 0 ? w.halfExtents[1] / std::abs(sv) : 1e300);
          return add(add(c, w.axes[0], (rim ? w.hole : reach) * cu), w.axes[1],
                     (rim ? w.hole : reach) * sv);
        };
        for (int j = 0; j < n; ++j)
          m.polygon({ray(j, true), ray(j, false), ray(j + 1, false), ray(j + 1, true)}, k);
        break;
      }
      m.polygon(rectangle(c, w.axes[0], w.halfExtents[0], w.axes[1], w.halfExtents[1]), k);
      break;
    }
    case WallShape::Box: {
      // Each face: the axis it faces along, and its two in-plane axes in right-handed order.
      for (int f = 0; f < 3; ++f) {
        const int a = (f + 1) % 3, b = (f + 2) % 3;
        for (int side : {-1, 1}) {
          const Vec3d fc = add(c, w.axes[f], side * w.halfExtents[f]);
          const int p = side > 0 ? a : b, q = side > 0 ? b : a;
          m.polygon(rectangle(fc, w.axes[p], w.halfExtents[p], w.axes[q], w.halfExtents[q]), k);
        }
      }
      break;
    }
    case WallShape::Mesh: {
      const physics::TriangleMesh& mesh = *w.mesh;
      const auto place = [&](const Vec3& x) {
        Vec3d out = c;
        for (int k = 0; k < 3; ++k) out = add(out, w.axes[k], x[k]);
        return out;
      };
      for (const auto& t : mesh.triangles) {
        m.polygon({place(mesh.vertices[t[0]]), place(mesh.vertices[t[1]]), place(mesh.vertices[t[2]])}, k);
      }
      break;
    }
    case WallShape::Drum: {
      const Vec3d axis = w.axes[0], u = perpendicular(axis), v = cross(axis, u);
      for (int j = 0; j < kDrumSegments; ++j) {
        const double t0 = 2 * M_PI * j / kDrumSegments, t1 = 2 * M_PI * (j + 1) / kDrumSegments;
        const Vec3d r0 = add(Vec3d{}, u, w.radius * std::cos(t0)),
                    r1 = add(Vec3d{}, u, w.radius * std::cos(t1));
        const Vec3d p0 = add(add(c, r0), v, w.radius * std::sin(t0)),
                    p1 = add(add(c, r1), v, w.radius * std::sin(t1));
        m.polygon({add(p0, axis, -w.halfLength), add(p1, axis, -w.halfLength),
                   add(p1, axis, w.halfLength), add(p0, axis, w.halfLength)},
                  k);
      }
      break;
    }
  }
}

}  // namespace

io::VtkPolyData elementsVtk(const sim::Simulation& s) {
  // The table's arrays are moved into the file's, not copied: copies of half a million
  // elements' arrays (with their first page faults) were a long unpolled stretch.
  sim::ElementTable t = s.elementTable();
  const size_t n = t.ids.size();
  InterruptPoll poll("writing the elements");
  VtkPolyData d;
  d.points = std::move(t.position);
  d.vertexPerPoint = true;
  std::vector<int64_t> ids(n);
  // (A distributed scene's elements under the ids the script knows, which they keep on any rank.)
  for (size_t i = 0; i < n; ++i) {
    poll();
    ids[i] = (s.distributed() ? s.originalHandle(t.ids[i]) : t.ids[i]).scriptId();
  }
  d.pointData.push_back({"id", 1, std::move(ids)});
  for (size_t k = 0; k < t.tagNames.size(); ++k)
    d.pointData.push_back({"tag_" + t.tagNames[k], 1, std::move(t.tagged[k])});
  const auto int32s = [&](const std::vector<uint32_t>& from) {
    std::vector<int32_t> to(from.size());
    for (size_t i = 0; i < from.size(); ++i) {
      poll();
      to[i] = int32_t(from[i]);
    }
    return to;
  };
  d.pointData.push_back({"material", 1, int32s(t.material)});
  d.pointData.push_back({"shape", 1, int32s(t.shape)});
  if (t.shapeParamCount > 0)
    d.pointData.push_back({"shape_params", int(t.shapeParamCount), std::move(t.shapeParams)});
  d.pointData.push_back({"radius", 1, std::move(t.radius)});
  d.pointData.push_back({"mass", 1, std::move(t.mass)});
  d.pointData.push_back({"velocity", 3, std::move(t.velocity)});
  d.pointData.push_back({"angular_velocity", 3, std::move(t.angularVelocity)});
  d.pointData.push_back({"force", 3, std::move(t.force)});
  d.pointData.push_back({"torque", 3, std::move(t.torque)});
  d.pointData.push_back({"orientation", 4, std::move(t.orientation)});
  d.fieldStrings.push_back({"material_names", t.materialNames});
  d.fieldStrings.push_back({"shape_names", t.shapeNames});
  stamp(s, d);
  return d;
}

io::VtkPolyData wallsVtk(const sim::Simulation& s) {
  WallMesh m;
  const std::array<Vec3d, 2> bounds = s.bounds();
  const std::vector<WallId> ids = s.wallIds();
  std::vector<sim::WallState> walls;
  for (WallId id : ids) walls.push_back(s.wall(id));
  if (s.distributed()) {
    // Each rank holds the force of its own elements' contacts: summed (collective).
    std::vector<double> f;
    for (const sim::WallState& w : walls) f.insert(f.end(), w.force.begin(), w.force.end());
    mpi::Communicator::world().sum(f);
    for (size_t k = 0; k < walls.size(); ++k) {
      walls[k].force = {f[3 * k], f[3 * k + 1], f[3 * k + 2]};
    }
  }
  std::vector<std::string> materials;
  std::vector<int32_t> materialOf;
  for (size_t k = 0; k < walls.size(); ++k) {
    meshWall(walls[k], s.dim(), bounds, k, m);
    auto it = std::find(materials.begin(), materials.end(), walls[k].material);
    materialOf.push_back(int32_t(it - materials.begin()));
    if (it == materials.end()) materials.push_back(walls[k].material);
  }
  std::vector<int64_t> wallId;
  std::vector<int32_t> material;
  std::vector<double> force;
  for (size_t k : m.wallOfCell) {
    wallId.push_back(ids[k].scriptId());
    material.push_back(materialOf[k]);
    force.insert(force.end(), walls[k].force.begin(), walls[k].force.end());
  }
  m.d.cellData.push_back({"wall", 1, std::move(wallId)});
  m.d.cellData.push_back({"material", 1, std::move(material)});
  m.d.cellData.push_back({"force", 3, std::move(force)});
  std::vector<std::string> names;
  for (const sim::WallState& w : walls) names.push_back(w.name);
  m.d.fieldStrings.push_back({"wall_names", names});
  m.d.fieldStrings.push_back({"material_names", materials});
  stamp(s, m.d);
  return std::move(m.d);
}

io::VtkPolyData contactsVtk(const sim::Simulation& s) {
  const std::vector<sim::ContactInfo> cs = s.contacts();
  VtkPolyData d;
  const size_t n = cs.size();
  std::vector<int64_t> a(n), b(n), wall(n);
  std::vector<double> force, normal, tangential, fn(n), overlap(n);
  force.reserve(3 * n), normal.reserve(3 * n), tangential.reserve(3 * n);
  // Reserved: grown by doubling, a million contacts' points were copied in unpolled calls.
  d.points.reserve(6 * n);
  d.lines.reserve(2 * n);
  InterruptPoll poll("writing the contacts");  // a command's; a run's outputs have no flag set
  for (size_t k = 0; k < n; ++k) {
    poll();
    const sim::ContactInfo& c = cs[k];
    const Vec3d start = c.centreA, end = c.b.isNull() ? c.point : c.centreB;
    d.points.insert(d.points.end(), start.begin(), start.end());
    d.points.insert(d.points.end(), end.begin(), end.end());
    d.lines.push_back(int64_t(2 * k));
    d.lines.push_back(int64_t(2 * k + 1));
    a[k] = c.a.scriptId();
    b[k] = c.b.isNull() ? -1 : c.b.scriptId();
    wall[k] = c.wall.isNull() ? -1 : c.wall.scriptId();
    fn[k] = dot(c.force, c.normal);
    const Vec3d ft = add(c.force, c.normal, -fn[k]);
    force.insert(force.end(), c.force.begin(), c.force.end());
    normal.insert(normal.end(), c.normal.begin(), c.normal.end());
    tangential.insert(tangential.end(), ft.begin(), ft.end());
    overlap[k] = c.overlap;
  }
  d.cellData.push_back({"a", 1, std::move(a)});
  d.cellData.push_back({"b", 1, std::move(b)});
  d.cellData.push_back({"wall", 1, std::move(wall)});
  d.cellData.push_back({"force", 3, std::move(force)});
  d.cellData.push_back({"normal", 3, std::move(normal)});
  d.cellData.push_back({"normal_force", 1, std::move(fn)});
  d.cellData.push_back({"tangential_force", 3, std::move(tangential)});
  d.cellData.push_back({"overlap", 1, std::move(overlap)});
  stamp(s, d);
  return d;
}

}  // namespace demlab::output
