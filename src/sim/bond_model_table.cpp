// The rows of the bond model table (sim/bond_model.hpp): one per model type.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "sim/bond_models/parallel_bond.hpp"
#include "sim/bond_models/point_spring.hpp"

namespace demlab::sim {

namespace {

// Returns the row of a model M with static options(), step<D>() and stiffness().
template <class M>
BondModelType row(std::string name, std::string summary, std::string details) {
  return {std::move(name),      std::move(summary),   std::move(details), M::options(),
          &M::template step<2>, &M::template step<3>, &M::stiffness};
}

}  // namespace

const std::vector<BondModelType>& bondModelTypes() {
  static const std::vector<BondModelType> rows = {
      row<PointSpringBond>(
          "pointspring", "a point-to-point cohesive spring (normal and shear, no moment)",
          "Strengths are forces: the bond breaks in tension when its normal pull exceeds "
          "-tensile, in shear when its shear force exceeds -shear."),
      row<ParallelBond>(
          "parallel", "Potyondy and Cundall's parallel bond (force and moment)",
          "A cemented cylinder (3D) or unit-thickness slab (2D) of radius lambda min(Ri, Rj): "
          "stiffnesses per area, strengths as stresses on the rim, sigma = Fn/A + |Mb| R/I, "
          "tau = |Fs|/A + |Mt| R/J."),
  };
  return rows;
}

uint32_t bondModelType(const std::string& name) {
  const auto& rows = bondModelTypes();
  std::string known;
  for (size_t k = 0; k < rows.size(); ++k) {
    if (rows[k].name == name) return static_cast<uint32_t>(k);
    known += (k == 0 ? "" : k + 1 == rows.size() ? ", or " : ", ") + rows[k].name;
  }
  throw Error("bad bond type \"" + name + "\": must be " + known, {"LOOKUP", "BONDTYPE"});
}

double bondOption(const BondModelType& t, const std::vector<double>& values,
                  const std::string& name) {
  for (size_t k = 0; k < t.options.size(); ++k) {
    if (t.options[k].name == name) return values[k];
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace demlab::sim
