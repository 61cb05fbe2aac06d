// CgField: fields sampled on a regular grid, as plain data a writer can store (a VTK image
// data file, a NumPy array) without knowing where they came from. No dependence on Tcl or on
// the simulation: a grid and named float64 arrays.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace demlab::analysis {

struct CgArray {
  std::string name;    // e.g. "density"
  int components = 1;  // 1 (scalar), 3 (vector: x y z), 9 (tensor: row-major xx xy xz yx ...)
  // components values per grid point, points in x-fastest order: point (i, j, k) starts at
  // components * (i + dims[0] * (j + dims[1] * k)).
  std::vector<double> values;
};

struct CgField {
  std::array<double, 3> origin{};   // the position of point (0, 0, 0)
  std::array<double, 3> spacing{};  // between neighbouring points along each axis (> 0)
  std::array<size_t, 3> dims{1, 1, 1};  // points along each axis (2D grids: dims[2] == 1)
  std::vector<CgArray> arrays;

  size_t points() const { return dims[0] * dims[1] * dims[2]; }
  // Returns the array named name, or nullptr.
  const CgArray* find(const std::string& name) const {
    for (const CgArray& a : arrays)
      if (a.name == name) return &a;
    return nullptr;
  }
};

}  // namespace demlab::analysis
