// Narrow phase: the contact geometry of a grain (sphere/disc) with another grain or with a wall
// shape (shapes.hpp), in 2D and 3D. Each intersect() returns the contact (unit normal from the
// grain A to B, overlap > 0, point in the middle of the overlap) or nothing when they do not
// touch; exactly touching (overlap 0) is not a contact. All are inline, allocation free, and
// take at most one sqrt (two over a flat wall's hole); the grain-grain and grain-drum tests
// reject with no sqrt at all.
//
// Dispatch by shape type: the table narrowPhaseRows<D>() holds one row per (grain, shape) pair
// with its routines behind a type-erased signature; registerNarrowPhase() puts the rows into a
// TypeInteractionManager (core/type_interaction.hpp), so a new shape is one new row. The sim
// looks the entry up once per pair of types (or per wall) and then either calls `one` per pair
// or, cheaper, `grains` once per wall with the batch of candidate grains.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "core/type_interaction.hpp"
#include "physics/contact.hpp"
#include "physics/shapes.hpp"

namespace demlab::physics {

template <int D>
std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const SphereShape<D>& b);
template <int D>
std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const PlaneShape<D>& b);
template <int D>
std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const FlatWallShape<D>& b);
template <int D>
std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const BoxShape<D>& b);
template <int D>
std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const DrumShape<D>& b);

// Type-erased routines of one row. a and b point at the row's shapes (a: SphereShape<D>).
template <int D>
using IntersectFn = std::optional<ContactGeometry<D>> (*)(const void* a, const void* b);
// Tests grains i = which[0..n) (centres[i], radii[i]) against the shape *b. Writes the contacts
// to out[0..m) and the grains they belong to to touched[0..m) (in the order of which); returns
// m <= n. Changes nothing else.
template <int D>
using IntersectGrainsFn = size_t (*)(const void* b, const VecD<D>* centres, const Real* radii,
                                     const uint32_t* which, size_t n, ContactGeometry<D>* out,
                                     uint32_t* touched);

template <int D>
struct NarrowPhaseEntry {
  IntersectFn<D> one = nullptr;
  IntersectGrainsFn<D> grains = nullptr;

  // Returns one(a, b), so TypeInteractionManager::dispatch(ta, tb, a, b) calls the routine
  // with the shapes in the row's order.
  std::optional<ContactGeometry<D>> operator()(const void* a, const void* b) const {
    return one(a, b);
  }
};

template <int D>
struct NarrowPhaseRow {
  std::string_view a;  // shape type names: "sphere", "plane", "flatwall", "box", "drum"
  std::string_view b;
  NarrowPhaseEntry<D> entry;
};

// Returns the table: one row per shape pair, a = "sphere" in every row. Changes nothing.
template <int D>
std::span<const NarrowPhaseRow<D>> narrowPhaseRows();

// Registers every row of narrowPhaseRows<D>() in table, adding the shape type names to types
// where missing. Returns nothing. Throws demlab::Error as TypeInteractionManager::add does
// ({EXISTS INTERACTION} if a row's pair is already in table); rows added before a throw stay.
template <int D>
void registerNarrowPhase(TypeRegistry& types, TypeInteractionManager<NarrowPhaseEntry<D>>& table);

}  // namespace demlab::physics

#include "physics/narrow_phase_impl.hpp"
