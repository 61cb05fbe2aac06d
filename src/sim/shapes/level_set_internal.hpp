// What the level set's files share (sim/shapes/level_set_grid.cpp, level_set_distance.cpp).
#pragma once

#include <array>
#include <span>

#include "sim/shapes/level_set.hpp"

namespace demlab::sim {

// Returns the number of nodes of a grid of n nodes per axis.
template <int D>
size_t nodeCount(const std::array<int, D>& n);

// Returns the per-axis indices of node i (x fastest).
template <int D>
std::array<int, D> nodeIndex(size_t i, const std::array<int, D>& n);

// Returns the surface where the values (one per node, x fastest) cross zero, by marching the
// cells' Kuhn simplices: triangles (3D) or segments (2D), each face's normal outward (towards
// the non-negative values), crossings shared between faces. Changes nothing.
template <int D>
Polytope<D> zeroLevelSurface(Real h, const std::array<int, D>& n, const VecD<D>& origin,
                             std::span<const double> values);

}  // namespace demlab::sim
