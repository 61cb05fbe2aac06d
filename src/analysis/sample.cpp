#include "analysis/sample.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>

#include "analysis/region_geometry.hpp"
#include "core/interrupt.hpp"
#include "mpi/records.hpp"

namespace demlab::analysis {

namespace {

// What a rank sends of its part of a distributed scene's sample: its elements and the
// contacts it computed, the elements named by the handles scripts know (bits; 0: none).
struct PackedElement {
  uint64_t id;
  double position[3], velocity[3], radius, mass, volume;
  uint64_t ball;
};
struct PackedContact {
  uint64_t a, b;
  int64_t wall;
  double point[3], normal[3], force[3];
};

// Returns the whole sample of a distributed scene on every rank, its elements in the order of
// their ids, from this rank's part `mine` (its own elements, the contacts it computed: their
// ends by the handle bits in ends, a's then b's, b 0 for a wall). Collective.
Sample gatherParts(const Sample& mine,
                   const std::vector<std::array<uint64_t, 2>>& ends) {
  std::vector<PackedElement> myElements;
  for (size_t i = 0; i < mine.size(); ++i) {
    PackedElement& e = myElements.emplace_back(PackedElement{
        mine.ids[i].bits(), {}, {}, mine.radius[i], mine.mass[i], mine.volume[i],
        uint64_t(mine.ball[i])});
    for (int k = 0; k < 3; ++k) e.position[k] = mine.position[i][k], e.velocity[k] = mine.velocity[i][k];
  }
  std::vector<PackedContact> myContacts;
  for (size_t k = 0; k < mine.contacts.size(); ++k) {
    const SampleContact& c = mine.contacts[k];
    PackedContact& p = myContacts.emplace_back(PackedContact{ends[k][0], ends[k][1], c.wall, {}, {}, {}});
    for (int q = 0; q < 3; ++q) p.point[q] = c.point[q], p.normal[q] = c.normal[q], p.force[q] = c.force[q];
  }
  const mpi::Communicator& world = mpi::Communicator::world();
  std::vector<PackedElement> elements = mpi::gatherRecords(world, myElements);
  const std::vector<PackedContact> contacts = mpi::gatherRecords(world, myContacts);
  const auto scriptOrder = [](const PackedElement& x, const PackedElement& y) {
    return sim::ElementId::fromBits(x.id).scriptId() < sim::ElementId::fromBits(y.id).scriptId();
  };
  std::sort(elements.begin(), elements.end(), scriptOrder);
  Sample s;
  s.dim = mine.dim;
  s.periodic = mine.periodic;
  std::unordered_map<uint64_t, uint32_t> indexOf;
  for (const PackedElement& e : elements) {
    indexOf.emplace(e.id, uint32_t(s.ids.size()));
    s.ids.push_back(sim::ElementId::fromBits(e.id));
    s.position.push_back({e.position[0], e.position[1], e.position[2]});
    s.velocity.push_back({e.velocity[0], e.velocity[1], e.velocity[2]});
    s.radius.push_back(e.radius), s.mass.push_back(e.mass), s.volume.push_back(e.volume);
    s.ball.push_back(char(e.ball));
  }
  for (const PackedContact& p : contacts) {
    SampleContact c;
    c.a = indexOf.at(p.a);
    c.b = p.b == 0 ? -1 : int64_t(indexOf.at(p.b));
    c.wall = p.wall;
    for (int q = 0; q < 3; ++q) c.point[q] = p.point[q], c.normal[q] = p.normal[q], c.force[q] = p.force[q];
    s.contacts.push_back(c);
  }
  return s;
}

}  // namespace

Sample gatherSample(const sim::Simulation& sim, bool withBonds) {
  Sample s;
  const int d = s.dim = sim.dim();
  s.periodic = sim.periodic();
  // Every element's state in one call (no ElementState per element).
  const sim::ElementTable t = sim.elementTable();
  s.ids = t.ids;
  const size_t n = s.ids.size();
  // A distributed scene: this rank's elements under the handles scripts know, and its contacts
  // (which name those handles), gathered with the other ranks' parts below.
  const bool distributed = sim.distributed();
  if (distributed) {
    for (sim::ElementId& id : s.ids) id = sim.originalHandle(id);
  }
  std::vector<std::array<uint64_t, 2>> ends;
  s.position.resize(n), s.velocity.resize(n);
  s.radius = t.radius;
  s.mass = t.mass;
  s.volume.resize(n), s.ball.resize(n);
  std::vector<double> density;  // by material index
  for (const std::string& m : t.materialNames) density.push_back(sim.material(m).density);
  std::unordered_map<uint32_t, uint32_t> denseOfSlot;
  // Ctrl-C polled in every loop: a sample of a few hundred thousand elements takes tenths of a
  // second under the sanitizers, and a query changes nothing.
  InterruptPoll poll("gathering the sample");
  for (size_t i = 0; i < n; ++i) {
    poll();
    for (int k = 0; k < d; ++k) {
      s.position[i][k] = t.position[3 * i + k];
      s.velocity[i][k] = t.velocity[3 * i + k];
    }
    const double r = t.radius[i];
    s.ball[i] = t.shape[i] == 0;  // the table's first shape is the ball
    s.volume[i] = s.ball[i] ? (d == 2 ? std::numbers::pi * r * r
                                      : 4.0 / 3.0 * std::numbers::pi * r * r * r)
                            : t.mass[i] / density[t.material[i]];
    denseOfSlot[s.ids[i].index] = uint32_t(i);
  }
  for (const sim::ContactInfo& c : sim.contacts()) {
    poll();
    SampleContact k;
    if (distributed) {
      ends.push_back({c.a.bits(), c.b.bits()});  // mapped to indices once gathered
    } else {
      k.a = denseOfSlot.at(c.a.index);
      k.b = c.b.isNull() ? -1 : int64_t(denseOfSlot.at(c.b.index));
    }
    k.wall = c.wall.isNull() ? -1 : int64_t(c.wall.index);
    k.point = c.point, k.normal = c.normal, k.force = c.force;
    s.contacts.push_back(k);
  }
  if (distributed) return gatherParts(s, ends);  // (distributed scenes have no bonds)
  if (!withBonds) return s;
  for (const sim::BondInfo& b : sim.bonds()) {
    poll();
    if (!b.intact) continue;
    SampleContact k;
    k.a = denseOfSlot.at(b.a.index);
    const uint32_t j = denseOfSlot.at(b.b.index);
    k.b = int64_t(j);
    Vec3d n{};
    double len2 = 0;
    for (int q = 0; q < d; ++q) {
      n[q] = s.position[j][q] - s.position[k.a][q];
      len2 += n[q] * n[q];
    }
    const double len = std::sqrt(len2);
    // Midway between the surfaces (any point of the line gives the pair's f (x) (x_b - x_a);
    // this one splits the branch as a contact between the two would).
    const double along = len > 0 ? (s.radius[k.a] + 0.5 * (len - s.radius[k.a] - s.radius[j])) / len : 0.5;
    for (int q = 0; q < 3; ++q) {
      k.normal[q] = len > 0 ? n[q] / len : 0;
      k.point[q] = s.position[k.a][q] + along * n[q];
    }
    k.force = b.force;
    s.bonds.push_back(k);
  }
  return s;
}

namespace {

// Returns v reduced to its nearest periodic image (the minimum image of sim/periodic.hpp:
// the Lees-Edwards gradient axis first, with its offset along the flow axis).
Vec3d nearestImage(const sim::PeriodicDef& p, Vec3d v, int dim) {
  const auto length = [&](int k) { return p.hi[k] - p.lo[k]; };
  if (p.shearRate != 0) {
    const double n = std::nearbyint(v[p.gradient] / length(p.gradient));
    v[p.gradient] -= n * length(p.gradient);
    v[p.flow] -= n * p.offset;
  }
  for (int k = 0; k < dim; ++k) {
    if ((p.axes >> k) & 1u) v[k] -= length(k) * std::nearbyint(v[k] / length(k));
  }
  return v;
}

}  // namespace

std::vector<Arm> armsOf(const Sample& s, const SampleContact& c) {
  std::vector<Arm> arms;
  auto arm = [&](uint32_t e, double sign) {
    Arm a{e, {}, {}};
    for (int k = 0; k < 3; ++k) {
      a.force[k] = sign * c.force[k];
      a.branch[k] = c.point[k] - s.position[e][k];
    }
    if (s.periodic.axes != 0) a.branch = nearestImage(s.periodic, a.branch, s.dim);
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
