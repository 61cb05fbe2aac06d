// The solid (packing) fraction of a region: the volume of the elements inside it over its
// volume (areas in 2D), a ball that straddles the boundary counted by the exact volume of its
// part inside (region_geometry.hpp).
#pragma once

#include "analysis/sample.hpp"

namespace demlab::analysis {

struct PackingResult {
  double fraction = 0;    // solid volume / region volume
  double solid = 0;       // the elements' volume inside
  double mass = 0;        // their mass inside (each element's mass x its fraction inside)
  double volume = 0;      // the region's
  size_t elements = 0;    // elements with some volume inside
  int64_t straddling = -1;  // dense index of a non-ball element across the boundary, or -1
};

// Returns the packing of region by the elements carrying the selection's tag (its region is
// not used). A non-ball element counts whole when its bounding ball is inside and not at all
// when it is outside; one across the boundary stops the sum and is named in straddling (its
// exact part inside is not computed). Changes nothing.
PackingResult packing(const Sample& s, const Selection& sel, const Region& region);

}  // namespace demlab::analysis
