// The narrow-phase table: one row per (grain, shape) pair. A new shape is its struct in
// shapes.hpp, its intersect() in narrow_phase_impl.hpp, and one row here.
#include "physics/narrow_phase.hpp"

#include <array>

namespace demlab::physics {

namespace {

template <int D, class Shape>
std::optional<ContactGeometry<D>> intersectOne(const void* a, const void* b) {
  return intersect(*static_cast<const SphereShape<D>*>(a), *static_cast<const Shape*>(b));
}

template <int D, class Shape>
size_t intersectGrains(const void* b, const VecD<D>* centres, const Real* radii,
                       const uint32_t* which, size_t n, ContactGeometry<D>* out,
                       uint32_t* touched) {
  const Shape& shape = *static_cast<const Shape*>(b);
  size_t m = 0;
  for (size_t j = 0; j < n; ++j) {
    const uint32_t i = which[j];
    if (auto c = intersect(SphereShape<D>{centres[i], radii[i]}, shape)) {
      out[m] = *c;
      touched[m] = i;
      ++m;
    }
  }
  return m;
}

template <int D, class Shape>
constexpr NarrowPhaseRow<D> row(std::string_view b) {
  return NarrowPhaseRow<D>{
      "sphere", b, NarrowPhaseEntry<D>{&intersectOne<D, Shape>, &intersectGrains<D, Shape>}};
}

template <int D>
constexpr std::array kRows{
    row<D, SphereShape<D>>("sphere"),     row<D, PlaneShape<D>>("plane"),
    row<D, FlatWallShape<D>>("flatwall"), row<D, BoxShape<D>>("box"),
    row<D, DrumShape<D>>("drum"),
};

}  // namespace

template <int D>
std::span<const NarrowPhaseRow<D>> narrowPhaseRows() {
  return kRows<D>;
}

template <int D>
void registerNarrowPhase(TypeRegistry& types, TypeInteractionManager<NarrowPhaseEntry<D>>& table) {
  for (const NarrowPhaseRow<D>& r : kRows<D>) {
    const std::optional<TypeId> fa = types.find(r.a);
    const TypeId ta = fa ? *fa : types.add(r.a);
    const std::optional<TypeId> fb = types.find(r.b);
    const TypeId tb = fb ? *fb : types.add(r.b);
    table.add(ta, tb, r.entry);
  }
}

template std::span<const NarrowPhaseRow<2>> narrowPhaseRows<2>();
template std::span<const NarrowPhaseRow<3>> narrowPhaseRows<3>();
template void registerNarrowPhase<2>(TypeRegistry&, TypeInteractionManager<NarrowPhaseEntry<2>>&);
template void registerNarrowPhase<3>(TypeRegistry&, TypeInteractionManager<NarrowPhaseEntry<3>>&);

}  // namespace demlab::physics
