// The interface between the bond module (sim/bond_module.hpp) and the bond models: the module
// measures a bond's kinematics over the step (axis, length, the relative displacement and
// rotation increments at the bond's centre, from the half-step velocities the drift used, so
// the increments are the step's exact displacements), and the model turns them into the force
// and moment on the bond's second element, updating the state it accumulates. A model is one
// file under sim/bond_models/ and one row in sim/bond_model_table.cpp; its options are declared
// in the row, from which `bond model TYPE` and its help are built.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/bond.hpp"

namespace demlab::sim {

template <int D>
struct BondKinematics {
  VecD<D> n;         // unit axis from the first element's centre to the second's
  Real length;       // centre distance now
  Real ra, rb;       // the elements' radii
  VecD<D> dShear;    // relative displacement of the second element at the centre, in the plane
  AngularD<D> dRot;  // relative rotation of the second element over the step
};

// What a model returns for one bond and step: force and moment on the second element (the
// first takes the opposite) and, when a strength is exceeded, how the bond breaks.
template <int D>
struct BondResponse {
  VecD<D> force = VecD<D>::Zero();
  AngularD<D> moment = ElementArrays<D>::zeroAngular();
  std::optional<BondBreakMode> breaks;
};

// What a bond adds to the stiffness the critical step sees: against relative translation
// (N/m) and relative rotation (N m / rad).
struct BondStiffness {
  Real translation = 0, rotation = 0;
};

// One declared option of a model: its name (the command's -name), unit, help, default (NaN:
// required) and smallest value (values must be >= min, or > min when strict).
struct BondOption {
  std::string name, unit, help;
  double fallback;
  double min = 0;
  bool strict = false;
};

template <int D>
using BondStepFn = BondResponse<D> (*)(const std::vector<double>& values, const Bond<D>& bond,
                                       const BondKinematics<D>& k, BondState<D>& state);

struct BondModelType {
  std::string name, summary, details;
  std::vector<BondOption> options;  // tensile and shear are among them (the strengths)
  // Each returns the response to one step's kinematics (dt = 0 gives zero increments) and
  // stores the accumulated state in state.
  BondStepFn<2> step2;
  BondStepFn<3> step3;
  // Returns the bond's stiffness between elements of radii ra, rb in dimension dim.
  BondStiffness (*stiffness)(const std::vector<double>& values, Real ra, Real rb, int dim);
};

// Returns the model types in table order. Changes nothing.
const std::vector<BondModelType>& bondModelTypes();
// Returns the index of the type named name. Throws {LOOKUP BONDTYPE} naming the known types.
uint32_t bondModelType(const std::string& name);
// Returns the value of option name among values of a model of type t (NaN when the type has no
// such option). Changes nothing.
double bondOption(const BondModelType& t, const std::vector<double>& values,
                  const std::string& name);

template <int D>
inline BondStepFn<D> bondStep(const BondModelType& t) {
  if constexpr (D == 2) {
    return t.step2;
  } else {
    return t.step3;
  }
}

// Returns the norm of an angular quantity (|w| in 3D, |w| of the scalar in 2D).
inline Real angularNorm(Real w) {
  return std::abs(w);
}
inline Real angularNorm(const Vec3& w) {
  return w.norm();
}

}  // namespace demlab::sim
