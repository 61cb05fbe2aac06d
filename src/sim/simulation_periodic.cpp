// SimulationManager<D>: periodic and Lees-Edwards boundaries (checking their Def, setting,
// reporting; the run start's check of the cell against the pairs' reach).
#include <algorithm>
#include <cmath>
#include <string>

#include "core/validity.hpp"
#include "sim/convert.hpp"
#include "sim/simulation_manager.hpp"

namespace demlab::sim {

namespace {

const char* const kAxisNames = "xyz";

[[noreturn]] void badCell(const std::string& why) {
  throw Error("bad periodic cell: " + why, {"VALUE", "CELL"});
}

}  // namespace

template <int D>
void SimulationManager<D>::setPeriodic(const PeriodicDef& def) {
  if ((def.axes >> D) != 0) {
    throw Error("bad periodic axes: a " + std::to_string(D) + "D scene has no axis " +
                    std::string(1, kAxisNames[D]),
                {"VALUE", "AXES"});
  }
  PeriodicBox<D> box;
  box.axes = static_cast<uint8_t>(def.axes);
  for (int k = 0; k < D; ++k) {
    const double lo = def.lo[k], hi = def.hi[k];
    const std::string axis(1, kAxisNames[k]);
    if (!(std::abs(lo) <= validity::kMaxCoordinate && std::abs(hi) <= validity::kMaxCoordinate))
      badCell(axis + " bounds must be finite and within 1e15 m of the origin");
    if (box.periodic(k) && !(lo < hi)) badCell(axis + " needs lo < hi");
    box.lo[k] = lo;
    box.hi[k] = hi;
  }
  if (!std::isfinite(def.shearRate)) {
    throw Error("bad shear rate \"" + physics::formatReal(def.shearRate) + "\": must be finite",
                {"VALUE", "RATE"});
  }
  if (def.shearRate != 0) {
    const bool axesOk = def.flow >= 0 && def.flow < D && def.gradient >= 0 && def.gradient < D &&
                        def.flow != def.gradient && box.periodic(def.flow) &&
                        box.periodic(def.gradient);
    if (!axesOk) {
      throw Error("bad shear: its flow and gradient axes must be two different periodic axes",
                  {"VALUE", "RATE"});
    }
    box.shearRate = def.shearRate;
    box.flow = def.flow;
    box.gradient = def.gradient;
  }
  if (box.any()) {
    if (s_.bonds.intact() > 0)
      throw Error("can't make the axes periodic: the scene has bonds (not supported yet)",
                  {"UNSUPPORTED", "PERIODIC"});
    if (std::any_of(s_.elements.a.geometry.begin(), s_.elements.a.geometry.end(),
                    [](uint32_t g) { return g != 0; })) {
      throw Error("can't make the axes periodic: the scene has shape elements (not supported yet)",
                  {"UNSUPPORTED", "PERIODIC"});
    }
  }
  // The same cell keeps its images' offset and the elements' unwrap offsets; a new one
  // starts both afresh.
  PeriodicBox<D>& p = s_.periodic;
  const bool sameCell = p.axes == box.axes && p.lo == box.lo && p.hi == box.hi;
  if (sameCell && box.shearRate != 0 && p.flow == box.flow && p.gradient == box.gradient) {
    box.offset = p.offset;
    box.offsetTravel = p.offsetTravel;
  }
  if (sameCell) {
    box.unwrap = std::move(p.unwrap);
    box.unwrapGeneration = std::move(p.unwrapGeneration);
  }
  p = std::move(box);
  s_.needRebuild = true;
  touchConfig();
}

template <int D>
PeriodicDef SimulationManager<D>::periodic() const {
  const PeriodicBox<D>& p = s_.periodic;
  PeriodicDef d;
  d.axes = p.axes;
  for (int k = 0; k < D; ++k) {
    d.lo[k] = p.lo[k];
    d.hi[k] = p.hi[k];
  }
  d.shearRate = p.shearRate;
  d.flow = p.flow;
  d.gradient = p.gradient;
  d.offset = p.offset;
  return d;
}

template <int D>
void SimulationManager<D>::checkPeriodic(double skin) const {
  const PeriodicBox<D>& p = s_.periodic;
  if (s_.bonds.intact() > 0)
    throw Error("can't run bonds across periodic boundaries: not supported yet",
                {"UNSUPPORTED", "PERIODIC"});
  if (s_.anyShapes || std::any_of(s_.elements.a.geometry.begin(), s_.elements.a.geometry.end(),
                                  [](uint32_t g) { return g != 0; })) {
    throw Error("can't run shape elements across periodic boundaries: not supported yet",
                {"UNSUPPORTED", "PERIODIC"});
  }
  const std::vector<Real>& r = s_.elements.a.r;
  if (r.empty()) return;
  const Real reach = 2 * *std::max_element(r.begin(), r.end()) + skin;
  for (int k = 0; k < D; ++k) {
    if (p.periodic(k) && !(p.length(k) > 2 * reach)) {
      badCell(std::string(1, kAxisNames[k]) + " length " + physics::formatReal(p.length(k)) +
              " m must exceed twice the largest reach of a pair (two radii and the skin), " +
              physics::formatReal(2 * reach) + " m");
    }
  }
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
