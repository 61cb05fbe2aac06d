// The registry of behavior types (thesis chapter 10's BehaviorManager, made open): one row per
// type with its name, its declared options and its factory. The options are declared once, in
// the type's info(): the command layer builds `behavior add TYPE` and its help from them, the
// checkpoint stores a behavior as its type name and these named parameters, and the factory
// takes them back. Adding a type is one file under sim/behaviors/ and one row in
// behavior_registry.cpp (doc/design.md, "What adding X takes").
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sim/behavior.hpp"
#include "sim/convert.hpp"

namespace demlab::sim {

struct BehaviorRow {
  BehaviorTypeInfo info;
  // Each returns a new behavior from parameters already checked against info.options (names,
  // kinds, sizes, required ones, the target); throws VALUE <NAME> on a bad value.
  std::unique_ptr<Behavior<2>> (*make2)(const std::vector<BehaviorParam>&);
  std::unique_ptr<Behavior<3>> (*make3)(const std::vector<BehaviorParam>&);
};

// Returns the row of a type B<D> that has static info() and make().
template <template <int> class B>
BehaviorRow behaviorRow() {
  return {B<2>::info(), &B<2>::make, &B<3>::make};
}

// Returns the rows in registry order (the order help lists them and the loop runs them).
const std::vector<BehaviorRow>& behaviorRegistry();
// Returns the row named name. Throws LOOKUP BEHAVIORTYPE naming the known types.
const BehaviorRow& findBehaviorRow(std::string_view name);

// Returns a behavior of the type named type from params after checking them against the
// row's options. Throws LOOKUP BEHAVIORTYPE, VALUE OPTION, VALUE TARGET, VALUE <NAME>. Does
// not check that a grain exists (the caller does; a checkpoint may hold a removed one).
template <int D>
std::unique_ptr<Behavior<D>> makeBehavior(std::string_view type,
                                          const std::vector<BehaviorParam>& params);

// ---- helpers for the types' factories and params() --------------------------------------

// Returns the parameter named name, or null.
inline const BehaviorParam* findParam(const std::vector<BehaviorParam>& ps, std::string_view name) {
  for (const BehaviorParam& p : ps) {
    if (p.name == name) return &p;
  }
  return nullptr;
}
// Returns the vector parameter named name (3 numbers), or def when absent.
inline Vec3d paramVec(const std::vector<BehaviorParam>& ps, std::string_view name,
                      Vec3d def = {0, 0, 0}) {
  const BehaviorParam* p = findParam(ps, name);
  return p ? Vec3d{p->numbers[0], p->numbers[1], p->numbers[2]} : def;
}
// Returns the number parameter named name, or def when absent.
inline double paramNumber(const std::vector<BehaviorParam>& ps, std::string_view name, double def) {
  const BehaviorParam* p = findParam(ps, name);
  return p ? p->numbers[0] : def;
}
inline BehaviorParam vecParam(std::string name, const Vec3d& v) {
  return {std::move(name), {v[0], v[1], v[2]}, {}, {}};
}
inline BehaviorParam numberParam(std::string name, double x) {
  return {std::move(name), {x}, {}, {}};
}
// Returns the "element" or "tag" parameter naming a behavior's target.
inline BehaviorParam targetParam(ElementId grain, const std::string& tag) {
  if (!grain.isNull()) return {"element", {}, {}, grain};
  return {"tag", {}, tag, {}};
}
// Calls fn(dense index) for a behavior's target: the grain (nothing once it is gone), or each
// grain carrying tag now.
template <int D, class F>
void forEachTarget(const Scene<D>& s, ElementId grain, const std::string& tag, F&& fn) {
  if (!grain.isNull()) {
    const uint32_t i = s.ownedIndexOfHandle != nullptr ? s.ownedIndexOfHandle(s, grain)
                                                       : s.elements.pool().findDense(grain);
    if (i != HandlePool<ElementKind>::kNpos) fn(i);
  } else if (s.ownedTagged != nullptr) {
    for (uint32_t i : s.ownedTagged(s, tag)) fn(i);
  } else {
    s.elements.tags().forEach(tag, [&](ElementId id) { fn(s.elements.pool().denseIndex(id)); });
  }
}
// Returns `grain 1.1` or `tag "bed"`.
inline std::string targetText(ElementId grain, const std::string& tag) {
  return grain.isNull() ? "tag \"" + tag + "\"" : "grain " + toString(grain);
}

}  // namespace demlab::sim
