// A table of one contact coefficient per pair of materials, for the sub-models beside the laws
// (rolling resistance, cohesion): the smaller of the two materials' values (the rule of the
// sliding friction), or the pair's own (Scene::pairMaterials puts it into both); zero for a
// sub-model the scene switched off (modelMaterials).
#pragma once

#include <algorithm>
#include <vector>

#include "sim/law_models.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

template <int D>
class PairTable {
 public:
  // Mixes field of every pair of s's materials.
  PairTable(const Scene<D>& s, Real physics::MaterialDef::*field) : nm_(s.nMat()), v_(nm_ * nm_) {
    for (size_t m = 0; m < nm_; ++m) {
      for (size_t k = 0; k < nm_; ++k) {
        const auto [a, b] = modelMaterials(s, m, k);
        v_[m * nm_ + k] = std::min(a.*field, b.*field);
      }
    }
  }
  // Returns the value of the pair of materials m and k.
  Real at(size_t m, size_t k) const { return v_[m * nm_ + k]; }

 private:
  size_t nm_;
  std::vector<Real> v_;  // row-major nMat x nMat
};

// Returns true if some material of s has a positive field, or some pair its own positive value
// (own: the same coefficient in PairCoefficients).
template <int D>
bool anyPositive(const Scene<D>& s, Real physics::MaterialDef::*field,
                 double PairCoefficients::*own) {
  return std::any_of(s.materials.begin(), s.materials.end(),
                     [&](const physics::MaterialDef& m) { return m.*field > 0; }) ||
         std::any_of(s.pairOverrides.begin(), s.pairOverrides.end(),
                     [&](const PairOverride& o) { return o.c.*own > 0; });
}

}  // namespace demlab::sim
