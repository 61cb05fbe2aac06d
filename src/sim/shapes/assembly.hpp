// The assembly shape type's parameter list from its members by name (sim/shapes/assembly.cpp):
// what `element assembly` returns for `element add -shape assembly -params`.
#pragma once

#include <string>
#include <vector>

#include "core/math.hpp"

namespace demlab::sim {

// One member as a user describes it: a shape type by name, its parameters (or, for the ball,
// its radius), and its place in the assembly's frame.
struct AssemblyMemberDef {
  std::string shape;
  std::vector<double> params;
  double radius = 0;                 // the ball's; 0 for other types
  std::vector<double> position;      // D numbers (m)
  std::vector<double> orientation;   // 3D a quaternion {w x y z} (normalised), 2D an angle; empty: none
};

// Returns the assembly's parameters in a D-dimensional scene: each member's type id, count,
// place and parameters, every member moved about its own centroid (its position moved to keep
// it where it was given) and its quaternion normalised. Throws demlab::Error {VALUE SHAPE} naming
// the member for an unknown type, bad parameters, a ball without a radius or another type with
// one, a position or orientation of the wrong size, or members that overlap. Changes nothing.
template <int D>
std::vector<double> assemblyParams(const std::vector<AssemblyMemberDef>& members);

}  // namespace demlab::sim
