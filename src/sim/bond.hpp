// Bonds between elements: cemented or glued pairs that carry force (and, for some models,
// moment) until a strength is exceeded, after which the pair interacts through the ordinary
// contact law alone. The bond acts in parallel with the contact law, as Potyondy and Cundall's
// parallel bond does, so breakage removes only the bond's part of the pair's force.
//
// The scene keeps its bonds in a store of their own (Scene::bonds): bonds are made by commands,
// not by the search, and live until removed, so they need neither the search's pair table nor
// its sweep. Each bond names its elements by handle (a dense order change leaves it valid) and
// keeps the state its model accumulates (shear force, moments) inline. The models are one file
// each under sim/bond_models/ and one row each in sim/bond_model_table.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.hpp"
#include "sim/obj_manager.hpp"

namespace demlab::sim {

// How a bond broke.
enum class BondBreakMode : uint8_t { Tension = 1, Shear = 2 };

// A named set of bond parameters (`bond model TYPE NAME ...`): the model type (an index into
// bondModelTypes()) and its values in the order the type declares its options.
struct BondModel {
  std::string name;
  uint32_t type = 0;
  std::vector<double> values;
};

// What a model accumulates between steps, and what it measured last step (for queries).
template <int D>
struct BondState {
  VecD<D> shearForce = VecD<D>::Zero();  // on the second element, in the bond plane
  AngularD<D> bendMoment =
      ElementArrays<D>::zeroAngular();  // on the second element, normal to the axis
  Real twistMoment = 0;                 // on the second element, along the axis (3D)
  // Last force pass: normal force on the second element along the axis (> 0 pulls it towards
  // the first: tension), the largest tensile and shear stress (or force) the criterion compares.
  Real normalForce = 0, sigma = 0, tau = 0;
  Real energy = 0;  // elastic energy held, J
};

template <int D>
struct Bond {
  uint32_t id = 0;  // stable, in creation order
  ElementId a, b;
  uint32_t model = 0;           // index into BondSet::models
  Real restLength = 0;          // centre distance when bonded
  Real tensile = 0, shear = 0;  // this bond's strengths (drawn once when a model scatters them)
  bool intact = true;
  BondState<D> state;
};

// One breakage, kept for plots and outputs.
template <int D>
struct BondBreak {
  uint32_t bond = 0;
  ElementId a, b;
  BondBreakMode mode = BondBreakMode::Tension;
  double time = 0;
  uint64_t step = 0;
  VecD<D> point = VecD<D>::Zero();  // the bond's centre when it broke
  double energy = 0;                // elastic energy it held, released
  double measure = 0;               // what exceeded the strength: sigma (tension) or tau (shear)
};

// A bond asked to break during a step (the bond module only appends; the manager applies them
// at the step's end with the scene's other deferred changes).
struct PendingBreak {
  uint32_t index;  // into BondSet::bonds
  BondBreakMode mode;
};

template <int D>
struct BondSet {
  std::vector<BondModel> models;
  std::vector<Bond<D>> bonds;  // creation order: the order forces are summed in
  std::vector<BondBreak<D>> breaks;
  uint32_t nextId = 1;
  size_t intact() const {
    size_t n = 0;
    for (const Bond<D>& b : bonds) n += b.intact;
    return n;
  }
  bool empty() const { return bonds.empty() && models.empty() && breaks.empty(); }
};

}  // namespace demlab::sim
