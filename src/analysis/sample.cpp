#include "analysis/sample.hpp"

#include <map>
#include <numbers>
#include <unordered_map>

#include "analysis/region_geometry.hpp"

namespace demlab::analysis {

Sample gatherSample(const sim::Simulation& sim) {
  Sample s;
  const int d = s.dim = sim.dim();
  s.ids = sim.elementIds();
  const size_t n = s.ids.size();
  const std::vector<double> x = sim.positions(), v = sim.velocities(), r = sim.radii();
  s.position.resize(n), s.velocity.resize(n);
  s.radius = r;
  s.mass.resize(n), s.volume.resize(n), s.ball.resize(n);
  std::map<std::string, double> density;  // by material name, looked up once each
  std::unordered_map<uint32_t, uint32_t> denseOfSlot;
  const std::string ballName = sim.shapeNames().front();
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < d; ++k) {
      s.position[i][k] = x[i * d + k];
      s.velocity[i][k] = v[i * d + k];
    }
    sim::ElementState e = sim.element(s.ids[i]);
    s.mass[i] = e.mass;
    s.ball[i] = e.shape == ballName;
    if (s.ball[i]) {
      s.volume[i] = d == 2 ? std::numbers::pi * r[i] * r[i]
                           : 4.0 / 3.0 * std::numbers::pi * r[i] * r[i] * r[i];
    } else {
      auto it = density.find(e.material);
      if (it == density.end())
        it = density.emplace(e.material, sim.material(e.material).density).first;
      s.volume[i] = e.mass / it->second;
    }
    denseOfSlot[s.ids[i].index] = uint32_t(i);
  }
  for (const sim::ContactInfo& c : sim.contacts()) {
    SampleContact k;
    k.a = denseOfSlot.at(c.a.index);
    k.b = c.b.isNull() ? -1 : int64_t(denseOfSlot.at(c.b.index));
    k.wall = c.wall.isNull() ? -1 : int64_t(c.wall.index);
    k.point = c.point, k.normal = c.normal, k.force = c.force;
    s.contacts.push_back(k);
  }
  return s;
}

std::vector<Arm> armsOf(const Sample& s, const SampleContact& c) {
  std::vector<Arm> arms;
  auto arm = [&](uint32_t e, double sign) {
    Arm a{e, {}, {}};
    for (int k = 0; k < 3; ++k) {
      a.force[k] = sign * c.force[k];
      a.branch[k] = c.point[k] - s.position[e][k];
    }
    arms.push_back(a);
  };
  arm(c.a, -1);
  if (c.b >= 0) arm(uint32_t(c.b), 1);
  return arms;
}

bool selects(const Sample& s, const Selection& sel, size_t i) {
  return sel.hasTag(i) && (!sel.region || holdsPoint(*sel.region, s.position[i], s.dim));
}

double armWeight(const Sample& s, const Selection& sel, const Arm& a) {
  if (!sel.hasTag(a.element)) return 0;
  if (!sel.region) return 1;
  const Vec3d& p = s.position[a.element];
  Vec3d q{p[0] + a.branch[0], p[1] + a.branch[1], p[2] + a.branch[2]};
  return segmentFractionInside(*sel.region, p, q, s.dim);
}

size_t selectedCount(const Sample& s, const Selection& sel) {
  size_t n = 0;
  for (size_t i = 0; i < s.size(); ++i) n += selects(s, sel, i);
  return n;
}

std::vector<char> firstOfPair(const Sample& s) {
  std::vector<char> first(s.contacts.size(), 1);
  for (size_t k = 1; k < s.contacts.size(); ++k) {
    const SampleContact &p = s.contacts[k - 1], &c = s.contacts[k];
    if (p.a == c.a && p.b == c.b && p.wall == c.wall) first[k] = 0;
  }
  return first;
}

}  // namespace demlab::analysis
