// A sphere against a triangle-mesh wall (physics/shapes.hpp MeshShape): one contact per surface
// feature it touches, so that a sphere on the edge or corner shared by several triangles feels
// one force there, not one from each.
//
// Each triangle near the sphere gives its point nearest the centre and the feature it lies on:
// the triangle's inside, one of its edges or one of its corners (the corners' numbers are the
// mesh's merged ones, so two triangles name a shared edge or corner alike). Contacts are kept
// once per feature; an edge or corner contact is dropped when a triangle holding that edge or
// corner touches the sphere with its inside (it is the same surface seen past that triangle's
// rim, as LIGGGHTS and Kremmer et al. treat it); the contacts left are the surface's real ones
// (a sphere in a valley between two faces keeps both).
#pragma once

#include <cstdint>

#include "physics/contact.hpp"
#include "physics/shapes.hpp"

namespace demlab::physics {

template <int D>
struct MeshContact {
  ContactGeometry<D> g;  // normal from the sphere to the mesh
  uint32_t feature = 0;  // its rank by depth (0: the deepest), which keys its spring
};

// Writes the contacts of sphere s with mesh m to out (the deepest max of them when there are
// more) and returns their count; 0 in 2D (no mesh walls there). Changes nothing else.
template <int D>
int sphereMeshContacts(const SphereShape<D>& s, const MeshShape<D>& m, MeshContact<D>* out, int max);

}  // namespace demlab::physics
