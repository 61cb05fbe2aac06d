// SimObjManager: owns the grains (thesis: the elements) of one scene. Their hot state lives
// in contiguous arrays, one per field (structure of arrays), indexed by a dense index that the
// HandlePool keeps packed through removals; names, tags and handles are the cold side.
// Walls are few and large and live apart (sim/wall.hpp).
#pragma once

#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/handle.hpp"
#include "core/interrupt.hpp"
#include "core/math.hpp"
#include "core/name_lookup.hpp"
#include "core/tag_table.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

// The largest global id an element can have (ElementArrays::globalId): 2^55 creations, beyond
// any run; the keys above it name walls where pair partners are ids (sim/scene.hpp).
inline constexpr uint64_t kMaxGlobalId = (uint64_t{1} << 55) - 1;

template <int D>
struct ElementArrays {
  std::vector<VecD<D>> x, v, f, fPrev;   // position, velocity, force now, force of last step
  std::vector<RotationD<D>> q;           // orientation
  std::vector<AngularD<D>> w, t, tPrev;  // angular velocity, torque now and last step
  std::vector<Real> r, invMass, invInertia;
  std::vector<uint32_t> material;  // index into the scene's material table
  std::vector<uint32_t> slot;      // handle slot index: the id used for pair histories
  // The element's global id: its creation index in the scene, never reused, the same on every
  // rank of a distributed run (each runs the same script). It orients pairs (the lower id is
  // A) so that two ranks computing the same pair compute it alike.
  std::vector<uint64_t> globalId;
  // Index into the scene's geometries (Scene::geometries, sim/shape.hpp): 0 is the ball, whose
  // size is r; an element of another shape has r as its bounding radius.
  std::vector<uint32_t> geometry;

  static constexpr uint64_t kSlotAsId = ~uint64_t{0};

  // Appends one grain at rest-initialised forces, its global id gid (kSlotAsId: sl). Changes
  // every array.
  void push(const VecD<D>& xi, const VecD<D>& vi, const AngularD<D>& wi, Real ri, Real invM,
            Real invI, uint32_t mat, uint32_t sl, uint32_t geom = 0, uint64_t gid = kSlotAsId) {
    x.push_back(xi);
    v.push_back(vi);
    f.push_back(VecD<D>::Zero());
    fPrev.push_back(VecD<D>::Zero());
    q.push_back(identityRotation());
    w.push_back(wi);
    t.push_back(zeroAngular());
    tPrev.push_back(zeroAngular());
    r.push_back(ri);
    invMass.push_back(invM);
    invInertia.push_back(invI);
    material.push_back(mat);
    slot.push_back(sl);
    globalId.push_back(gid == kSlotAsId ? uint64_t{sl} : gid);
    geometry.push_back(geom);
  }

  // Applies a swap-remove to every array.
  void remove(SwapRemove m) {
    forEachArray(*this, [m](auto& arr) { applySwapRemove(arr, m); });
  }

  size_t size() const { return x.size(); }

  // Makes room for n grains in every array, exactly: adding up to n grains then reallocates
  // nothing (grown one by one the arrays would double, holding up to twice their size).
  void reserve(size_t n) {
    forEachArray(*this, [n](auto& arr) { arr.reserve(n); });
  }

  // Makes the arrays' reserved room for n grains resident, their contents unchanged (see
  // touchRoom, core/interrupt.hpp). Throws {INTERRUPTED}, every array as it was.
  void touchRoom(size_t n, std::string_view what) {
    forEachArray(*this, [&](auto& arr) {
      using T = typename std::decay_t<decltype(arr)>::value_type;
      demlab::touchRoom(arr, n, blank<T>(), what);
    });
  }

  // Returns the bytes of heap the arrays hold (their capacity).
  size_t heapBytes() const {
    size_t bytes = 0;
    forEachArray(*this, [&](const auto& arr) { bytes += arr.capacity() * sizeof(arr[0]); });
    return bytes;
  }

  // Applies fn to every array of self (a ElementArrays, const or not).
  template <class Self, class F>
  static void forEachArray(Self& self, F&& fn) {
    fn(self.x), fn(self.v), fn(self.f), fn(self.fPrev), fn(self.q), fn(self.w), fn(self.t);
    fn(self.tPrev), fn(self.r), fn(self.invMass), fn(self.invInertia), fn(self.material);
    fn(self.slot), fn(self.globalId), fn(self.geometry);
  }

  // Returns a defined value of an array's type: zero, or the identity rotation.
  template <class T>
  static T blank() {
    if constexpr (std::is_arithmetic_v<T>) {
      return T(0);
    } else if constexpr (requires { T::Zero(); }) {
      return T::Zero();
    } else if constexpr (requires { T::Identity(); }) {
      return T::Identity();
    } else {
      return T::identity();
    }
  }

  static RotationD<D> identityRotation() {
    if constexpr (D == 2) {
      return Rotation2::identity();
    } else {
      return Quat::Identity();
    }
  }
  static AngularD<D> zeroAngular() {
    if constexpr (D == 2) {
      return 0.0;
    } else {
      return Vec3::Zero();
    }
  }
};

// Returns the mass and the moment of inertia of a grain of density rho and radius r.
// 2D grains are discs of unit thickness: m = rho pi r^2, I = m r^2 / 2 (the disc's 2/3 rolling
// factor); 3D grains are spheres: m = 4/3 rho pi r^3, I = 2/5 m r^2.
template <int D>
inline Real ballMass(Real rho, Real r) {
  if constexpr (D == 2) {
    return rho * std::numbers::pi * r * r;
  } else {
    return rho * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
}
template <int D>
inline Real ballInertia(Real mass, Real r) {
  return (D == 2 ? 0.5 : 0.4) * mass * r * r;
}

template <int D>
class SimObjManager {
 public:
  SimObjManager() : pool_("grain"), names_("grain") {}

  ElementArrays<D> a;  // the hot state; dense index i is pool().handleAt(i)

  // The neighbor search sorts the dense order spatially at every reorderEvery-th search
  // (sim/reorder.hpp); 0: never. A tuning knob, not part of the scene: checkpoints do not
  // save it. Between two sorts grains drift little (a search happens when one has moved half
  // a skin), and a sort costs about as much as one contact pass of a dense bed.
  uint32_t reorderEvery = kDefaultReorderEvery;
  static constexpr uint32_t kDefaultReorderEvery = 10;

  const HandlePool<ElementKind>& pool() const { return pool_; }
  HandlePool<ElementKind>& pool() { return pool_; }
  NameLookup<ElementId>& names() { return names_; }
  const NameLookup<ElementId>& names() const { return names_; }
  TagTable<ElementKind>& tags() { return tags_; }
  const TagTable<ElementKind>& tags() const { return tags_; }

  // Returns the dense index of id. Throws {LOOKUP HANDLE}.
  uint32_t index(ElementId id) const { return pool_.denseIndex(id); }

  // Adds a grain whose Def was checked. Returns its handle. Changes every array, the pool,
  // names and tags (the caller has checked the name is free and the tags valid).
  ElementId add(const VecD<D>& x, const VecD<D>& v, const AngularD<D>& w, Real r, Real invM,
              Real invI, uint32_t mat, const std::string& name,
              const std::vector<std::string>& tagList, uint32_t geometry = 0) {
    const uint64_t gid = peekGlobalId();
    const ElementId id = pool_.allocate();
    a.push(x, v, w, r, invM, invI, mat, id.index, geometry, gid);
    nextGlobalId_ = gid + 1;
    if (!name.empty()) names_.add(name, id);
    for (const std::string& t : tagList) tags_.add(id, t);
    return id;
  }

  // Returns a new handle for an element whose arrays the caller appends itself, with global
  // id gid (an element arriving from another rank of a distributed run). Changes the pool.
  ElementId adopt(uint64_t gid) {
    nextGlobalId_ = std::max(nextGlobalId_, gid + 1);
    return pool_.allocate();
  }

  // Removes the grain id (live). Returns its slot index (for the pair histories to forget).
  uint32_t remove(ElementId id) {
    const SwapRemove m = pool_.free(id);
    a.remove(m);
    names_.remove(id);
    tags_.removeObject(id);
    return id.index;
  }

  size_t size() const { return a.size(); }

  // The global id the next element added gets: one more than the last given, never reused.
  uint64_t nextGlobalId() const { return nextGlobalId_; }
  // Returns nextGlobalId(), or throws {LIMIT COUNT} when the scene has made every id there is.
  uint64_t peekGlobalId() const {
    if (nextGlobalId_ > kMaxGlobalId) {
      throw Error("too many elements created in this scene (2^55)", {"LIMIT", "COUNT"});
    }
    return nextGlobalId_;
  }
  // Sets it (a checkpoint's load; n above every id held). Changes the counter only.
  void setNextGlobalId(uint64_t n) { nextGlobalId_ = n; }

 private:
  HandlePool<ElementKind> pool_;
  uint64_t nextGlobalId_ = 0;
  NameLookup<ElementId> names_;
  TagTable<ElementKind> tags_;
};

}  // namespace demlab::sim
