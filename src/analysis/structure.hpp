// The contact network of a selection of elements: coordination numbers and the fabric tensor.
#pragma once

#include "analysis/sample.hpp"
#include "analysis/tensor.hpp"

namespace demlab::analysis {

// Coordination of the elements selects() counts. An element's contacts are its distinct
// partners (another element, or a wall when walls are counted), whether or not they are
// selected; the several points of a shape pair count once.
struct Coordination {
  size_t elements = 0;  // N
  size_t ends = 0;      // the summed contacts of the elements (2C when all are inside)
  size_t rattlers0 = 0, rattlers1 = 0;  // N0, N1: elements with no contact, with one
  double plain = 0;       // Z = ends / N
  double mechanical = 0;  // Thornton's Z_m = (ends - N1) / (N - N0 - N1); 0 if no element
                          // has two contacts
};

// Returns the coordination of the selection (walls: count wall contacts). Changes nothing.
Coordination coordination(const Sample& s, const Selection& sel, bool walls);

// The fabric phi = sum w n (x) n / sum w over the contacts (Satake 1982), each weighted by the
// fraction of its branch (both arms) that the selection holds (armWeight, by length), so that
// a contact inside counts 1.
struct Fabric {
  Tensor tensor{};
  double contacts = 0;  // sum w: the contacts counted
};

// Returns the fabric of the selection (walls: count wall contacts, whose normal is the wall's).
// contacts is 0 when no contact counts (the tensor is then zero). Changes nothing.
Fabric fabric(const Sample& s, const Selection& sel, bool walls);

}  // namespace demlab::analysis
