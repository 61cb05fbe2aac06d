// The contact pass of pairs with an element that is not a ball (the ball pairs run through
// sim/contacts.hpp's passes). For each candidate the ShapeTable's row for the two shape types
// gives the contact points (sim/shape.hpp); each point goes through the scene's contact law for
// the material pair, with the lever arms from each element's centre to the point, so normal
// forces off the centre line turn the elements. Each point keeps its own tangential spring,
// keyed by the pair's slots and the point's feature id (Scene::shapeSprings); a point that
// stops touching drops its spring.
//
// The effective mass is the mass along the normal at the point, lever arms included:
// 1/m* = 1/m_a + 1/m_b + (r_a x n) . I_a^-1 (r_a x n) + (r_b x n) . I_b^-1 (r_b x n), so that
// the damping calibrated for a restitution e gives e in the normal velocity of the contact
// point whatever the point (a corner of a box as much as a ball's centre line, where the lever
// terms vanish). LIGGGHTS's superquadric pair keeps m_a m_b / (m_a + m_b), which over-damps a
// corner's impact. The effective radius is the row's curvature at the point.
#pragma once

#include <algorithm>
#include <vector>

#include "core/thread_pool.hpp"

#include "sim/contacts.hpp"
#include "sim/element_chunks.hpp"
#include "sim/element_marks.hpp"
#include "sim/member_balls.hpp"
#include "sim/rigid_body.hpp"
#include "sim/scene.hpp"
#include "sim/shape.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns element i of s as the contact routines see it.
template <int D>
ElementRef<D> elementRef(const Scene<D>& s, uint32_t i) {
  const ElementArrays<D>& a = s.elements.a;
  return {a.x[i], a.q[i], a.r[i], s.geometries[a.geometry[i]].get(), s.curvatureModel == 1};
}

// Returns a's contact points with b from the table (normals from a to b), into out. Throws
// {LOOKUP INTERACTION} if no routine serves the pair (the run checks before it starts).
template <int D>
int elementPairPoints(const Scene<D>& s, uint32_t i, uint32_t j, ContactPoint<D>* out) {
  return shapePairPoints(elementRef(s, i), elementRef(s, j), out);
}

// Returns element e's contact points with wall w, into out.
template <int D>
int elementWallPoints(const ElementRef<D>& e, const Wall<D>& w, ContactPoint<D>* out) {
  const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, w.shape);
  return shapeWallPoints(e, w.kind, shape, out);
}
template <int D>
int elementWallPoints(const Scene<D>& s, uint32_t i, const Wall<D>& w, ContactPoint<D>* out) {
  return elementWallPoints(elementRef(s, i), w, out);
}

// Throws {LOOKUP INTERACTION} unless the ShapeTable has a routine for every pair of shape types
// that can meet among s's elements and for every shape type against every kind of wall in s (balls with
// balls and walls excepted: the ball passes serve them), counting the types in extra as
// elements about to be added. Changes nothing.
template <int D>
void checkShapeRoutines(const Scene<D>& s, const std::vector<TypeId>& extra = {}) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  std::vector<size_t> present(s.geometries.size(), 0);
  for (uint32_t g : s.elements.a.geometry) present[g] += 1;
  std::vector<TypeId> types;
  std::vector<size_t> counts;  // elements of each type
  const auto count = [&](TypeId id, size_t n) {
    const auto it = std::find(types.begin(), types.end(), id);
    if (it == types.end()) {
      types.push_back(id);
      counts.push_back(n);
    } else {
      counts[static_cast<size_t>(it - types.begin())] += n;
    }
  };
  for (size_t g = 0; g < present.size(); ++g) {
    if (present[g] == 0) continue;
    const Geometry<D>& geom = *s.geometries[g];
    count(geom.shape, present[g]);
    // An assembly's members meet what it meets, through their own rows.
    for (TypeId m : t.type(geom.shape).memberTypes(geom.params)) count(m, present[g]);
  }
  // Elements about to be created (a deferred change): one more of each type.
  for (const TypeId id : extra) count(id, 1);
  for (size_t x = 0; x < types.size(); ++x) {
    for (size_t y = x; y < types.size(); ++y) {
      if (types[x] == ShapeTable<D>::ball() && types[y] == ShapeTable<D>::ball()) continue;
      if (x == y && counts[x] < 2) continue;  // a lone element of its type meets no other
      if (t.pair(types[x], types[y]) == nullptr) {
        throwNoRoutine(t.type(types[x]).name(), t.type(types[y]).name());
      }
    }
    if (types[x] == ShapeTable<D>::ball()) continue;
    for (const Wall<D>& w : s.walls.items) {
      const ElementWallEntry<D>* e = t.wall(types[x], w.kind);
      if (e == nullptr || e->fn == nullptr) throwNoRoutine(t.type(types[x]).name(), "a wall");
    }
  }
}

// Returns u . I^-1 u for element i and an angular vector u (in 2D a scalar: u^2 / I).
template <int D>
Real inverseInertiaAlong(const Scene<D>& s, uint32_t i, const AngularD<D>& u) {
  if constexpr (D == 3) {
    if (s.elements.a.invInertia[i] == 0) return u.dot(rigidInverseInertiaTimes(s, i, u));
  }
  return squaredNorm(u) * s.elements.a.invInertia[i];
}


template <int D>
class ShapeContactModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "shape-contacts"; }
  SimLevel level() const override { return SimLevel::Contacts; }

  void run(Scene<D>& s) override {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt, lag = velocityLag(s);
    const size_t nMat = s.nMat();
    const bool history = s.keepHistory, rotating = s.rotating;
    const bool localCurvature = s.curvatureModel == 1;  // law -curvature local
    PassEnergy e;
    // Pairs of ball unions go through the ball kernel when it can serve the scene; the rows
    // take the rest, first, on the thread pool: each chunk of candidates writes its points to
    // its own buffer, so the laws, springs and sums below see them in candidate order, as a
    // serial pass would, for any thread count. The rows are most of a shape pair's cost.
    members_ = ballUnions_.serves(s);
    listRows(s);
    placeElements(s);
    findPoints(s);
    if (rotating) worldInverseInertia(s);
    // One contact point through the law: returns the force on B.
    const auto apply = [&](const ContactPoint<D>& p, const VecD<D>& vrel, Real effMass, size_t pair,
                           const ShapeSpringKey& key) {
      physics::TangentialHistory<D>* h = nullptr;
      if (history) {
        // A new point starts from a zero spring; the map allocates only then.
        h = s.shapeSprings.touch(key);
      }
      const Real radius = p.hertzRadius(localCurvature);
      const physics::ContactKinematics<D> k{vrel, effMass, radius, lag};
      const physics::ContactForce<D> f = s.pairLawFn[pair](s.pairParams[pair], p.g, k, h, dt);
      e.add(f);
      return f.force;
    };
    if (history) s.shapeSprings.beginStep();
    if (members_) ballUnions_.run(s, e);
    for (size_t ci = 0; ci < rows_.size(); ++ci) {
      const uint32_t i = s.shapeCandidates[rows_[ci]].i, j = s.shapeCandidates[rows_[ci]].j;
      const Chunk& chunk = chunks_[ci / kChunk];
      const ContactPoint<D>* pts = chunk.points.data() + chunk.first[ci % kChunk];
      const int n = static_cast<int>(chunk.first[ci % kChunk + 1] - chunk.first[ci % kChunk]);
      const size_t pair = a.material[i] * nMat + a.material[j];
      const bool unions = n > 0 && !members_ && madeOfBalls(s, i) && madeOfBalls(s, j);
      for (int k = 0; k < n; ++k) {
        const VecD<D> ra = pts[k].g.point - a.x[i], rb = pts[k].g.point - a.x[j];
        const VecD<D>& nrm = pts[k].g.normal;
        // Ball unions meet as balls do: the bodies' reduced mass (sim/member_balls.hpp).
        const Real effMass =
            unions ? 1 / (a.invMass[i] + a.invMass[j])
                   : 1 / (a.invMass[i] + a.invMass[j] + compliance(s, i, ra, nrm) +
                          compliance(s, j, rb, nrm));
        VecD<D> vrel = a.v[j] - a.v[i];
        if (rotating) vrel += cross(a.w[j], rb) - cross(a.w[i], ra);
        const VecD<D> f =
            apply(pts[k], vrel, effMass, pair, {a.slot[i], a.slot[j], pts[k].feature});
        a.f[j] += f;
        a.f[i] -= f;
        if (rotating) {
          a.t[j] += cross(rb, f);
          a.t[i] -= cross(ra, f);
        }
        if (s.recordContacts) appendRecord<D>(s.contacts, {i, j, false, f});
      }
    }
    const size_t firstWall = rows_.size();
    for (size_t wi = 0; wi < s.shapeWallCandidates.size(); ++wi) {
      const auto [i, w] = s.shapeWallCandidates[wi];
      Wall<D>& wall = s.walls.items[w];
      const size_t ci = firstWall + wi;
      const Chunk& chunk = chunks_[ci / kChunk];
      const ContactPoint<D>* pts = chunk.points.data() + chunk.first[ci % kChunk];
      const int n = static_cast<int>(chunk.first[ci % kChunk + 1] - chunk.first[ci % kChunk]);
      const size_t pair = a.material[i] * nMat + wall.material;
      const uint32_t wallKey = wallPairId(s.walls.pool().handleAt(w).index);
      for (int k = 0; k < n; ++k) {
        const VecD<D> ra = pts[k].g.point - a.x[i];
        const VecD<D> vWall = wall.surfaceVelocity(pts[k].g.point);
        VecD<D> vrel = vWall - a.v[i];
        if (rotating) vrel -= cross(a.w[i], ra);
        const Real effMass = 1 / (a.invMass[i] + compliance(s, i, ra, pts[k].g.normal));
        const VecD<D> f = apply(pts[k], vrel, effMass, pair,
                                {a.slot[i], wallKey, pts[k].feature});
        a.f[i] -= f;
        if (rotating) a.t[i] -= cross(ra, f);
        wall.force += f;
        if (wall.moving) {
          e.wallWork -= f.dot(vWall) * dt;
          wall.work -= f.dot(vWall) * dt;
        }
        if (s.recordContacts) appendRecord<D>(s.contacts, {i, w, true, f});
      }
    }
    // The points that stopped touching drop their springs.
    if (history) s.shapeSprings.endStep();
    s.ledger.elastic += e.elastic;
    s.ledger.dampingLoss += e.damping;
    s.ledger.frictionLoss += e.friction;
    s.ledger.springWork += e.springWork;
    s.ledger.wallWork += e.wallWork;
  }

  size_t workingBytes() const override {
    size_t bytes = chunks_.capacity() * sizeof(Chunk) + invIw_.capacity() * sizeof(Mat3) +
                   placed_.capacity() * sizeof(double) + placedAt_.capacity() * sizeof(size_t) +
                   toPlace_.capacity() * sizeof(uint32_t) + placedMarks_.heapBytes() +
                   inertiaMarks_.heapBytes();
    bytes += ballUnions_.workingBytes() + rows_.capacity() * sizeof(uint32_t);
    for (const Chunk& c : chunks_) {
      bytes += c.points.capacity() * sizeof(ContactPoint<D>) + c.first.capacity() * sizeof(uint32_t);
    }
    return bytes;
  }

 private:
  static constexpr size_t kChunk = 64;  // candidates a task
  // One task's candidates' points: candidate k's are points[first[k] .. first[k + 1]).
  struct Chunk {
    std::vector<ContactPoint<D>> points;
    std::vector<uint32_t> first;
  };

  // Fills chunks_ with the points of every element pair and then every element-wall pair,
  // numbered in that order, on the thread pool. Throws {LOOKUP INTERACTION} as the rows do (the
  // lowest candidate's). Changes chunks_.
  void findPoints(const Scene<D>& s) {
    const size_t pairs = rows_.size(), total = pairs + s.shapeWallCandidates.size();
    const size_t nChunks = (total + kChunk - 1) / kChunk;
    if (chunks_.size() < nChunks) chunks_.resize(nChunks);
    const auto fill = [&](size_t c) {
      Chunk& chunk = chunks_[c];
      chunk.points.clear();
      chunk.first.assign(1, 0);
      ContactPoint<D> pts[kMaxContactPoints];
      const size_t end = std::min(total, (c + 1) * kChunk);
      for (size_t k = c * kChunk; k < end; ++k) {
        int n;
        if (k < pairs) {
          const auto [i, j] = s.shapeCandidates[rows_[k]];
          n = shapePairPoints(ref(s, i), ref(s, j), pts);
        } else {
          const auto& [i, w] = s.shapeWallCandidates[k - pairs];
          n = elementWallPoints(ref(s, i), s.walls.items[w], pts);
        }
        chunk.points.insert(chunk.points.end(), pts, pts + n);
        chunk.first.push_back(static_cast<uint32_t>(chunk.points.size()));
      }
    };
    if (nChunks <= 1) {
      if (nChunks == 1) fill(0);
      return;
    }
    ThreadPool::global().forEach(nChunks, [&](size_t c, unsigned) { fill(c); });
  }

  // Lists in rows_ the candidates the rows serve this step: all, or those the member pass does
  // not. Changes rows_.
  void listRows(const Scene<D>& s) {
    rows_.clear();
    for (uint32_t k = 0; k < s.shapeCandidates.size(); ++k) {
      const auto [i, j] = s.shapeCandidates[k];
      if (!members_ || !madeOfBalls(s, i) || !madeOfBalls(s, j)) rows_.push_back(k);
    }
  }

  // Writes the placed form (ShapeType::place) of each element that has one and a candidate
  // of the rows this step to placed_, at placedAt_[i]; on the thread pool. Changes placed_,
  // placedAt_, placedMarks_ and toPlace_.
  void placeElements(const Scene<D>& s) {
    const ElementArrays<D>& a = s.elements.a;
    placedMarks_.begin(a.size());
    placedAt_.resize(a.size());
    toPlace_.clear();
    size_t size = 0;
    const auto mark = [&](uint32_t i) {
      const uint32_t n = s.geometries[a.geometry[i]]->placedSize;
      if (n == 0 || !placedMarks_.mark(i)) return;
      placedAt_[i] = size;
      toPlace_.push_back(i);
      size += n;
    };
    for (const uint32_t k : rows_) mark(s.shapeCandidates[k].i), mark(s.shapeCandidates[k].j);
    for (const auto& c : s.shapeWallCandidates) mark(c.first);
    placed_.resize(size);
    const ShapeTable<D>& t = ShapeTable<D>::get();
    forEachElementChunk(toPlace_.size(), [&](size_t begin, size_t end, size_t) {
      for (size_t k = begin; k < end; ++k) {
        const uint32_t i = toPlace_[k];
        const ElementRef<D> e = elementRef(s, i);
        t.type(e.g->shape).place(e, placed_.data() + placedAt_[i]);
      }
    });
  }
  // Returns element i as the rows see it, with its placed form when its type has one.
  ElementRef<D> ref(const Scene<D>& s, uint32_t i) const {
    ElementRef<D> e = elementRef(s, i);
    if (e.g->placedSize != 0) e.placed = placed_.data() + placedAt_[i];
    return e;
  }

  // Makes invIw_[i], the world inverse inertia tensor of each element i of anisotropic inertia
  // (3D) that the rows' points reach this step, once a step: a point would otherwise turn both
  // bodies' principal frames. Changes invIw_.
  void worldInverseInertia(const Scene<D>& s) {
    if constexpr (D == 3) {
      const ElementArrays<D>& a = s.elements.a;
      invIw_.resize(a.size());
      inertiaMarks_.begin(a.size());
      const auto make = [&](uint32_t i) {
        if (a.invInertia[i] != 0 || !inertiaMarks_.mark(i)) return;
        const PrincipalFrame f = principalFrame(s, i);
        const Mat3 r = f.Q.toRotationMatrix();
        invIw_[i] = r * f.I.cwiseInverse().asDiagonal() * r.transpose();
      };
      for (const uint32_t k : rows_) make(s.shapeCandidates[k].i), make(s.shapeCandidates[k].j);
      for (const auto& c : s.shapeWallCandidates) make(c.first);
    }
  }
  // Returns (r x n) . I^-1 (r x n) for element i: the rotational part of its compliance along
  // the normal n at the lever arm r (0 when the scene does not rotate), by invIw_ for a rigid one.
  Real compliance(const Scene<D>& s, uint32_t i, const VecD<D>& r, const VecD<D>& n) const {
    if (!s.rotating) return 0;
    const AngularD<D> u(cross(r, n));
    if constexpr (D == 3) {
      if (s.elements.a.invInertia[i] == 0) return u.dot(invIw_[i] * u);
    }
    return squaredNorm(u) * s.elements.a.invInertia[i];
  }

  std::vector<Chunk> chunks_;
  MemberBallPass<D> ballUnions_;
  bool members_ = false;  // ballUnions_ serves this step's pairs of ball unions
  std::vector<uint32_t> rows_;  // the candidates the rows serve this step
  std::vector<double> placed_;          // the placed forms of this step
  std::vector<size_t> placedAt_;        // per element (dense): where its placed form starts
  ElementMarks placedMarks_;           // the elements placed this step
  std::vector<uint32_t> toPlace_;
  ElementMarks inertiaMarks_;          // the elements whose invIw_ was made this step
  std::vector<Mat3> invIw_;  // per element (dense), valid for the rigid ones this step
};

}  // namespace demlab::sim
