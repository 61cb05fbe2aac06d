// A scene as VTK PolyData for ParaView: the elements (a vertex per element with every field),
// the walls (their surfaces: polygons in 3D, lines in 2D, with their forces) and the contact
// network (a line per contact with its forces). Coordinates are 3D in every file (2D: z = 0).
#pragma once

#include "io/vtk_xml.hpp"
#include "sim/simulation.hpp"

namespace demlab::output {

// Returns the elements of s: point data id, tag_<name> (0/1 per tag), material (an index into
// the field data material_names), shape (into shape_names), shape_params, radius, mass,
// velocity, angular_velocity, force, torque, orientation (quaternion w x y z); field data
// TIME, STEP. A distributed scene: this rank's elements, not its ghosts.
io::VtkPolyData elementsVtk(const sim::Simulation& s);

// Returns the walls of s as surfaces. Infinite planes are drawn as a square (3D) or segment
// (2D) across the scene's bounds. Cell data per polygon or line: wall (its id), force (on the
// wall, the whole wall's), material; field data wall_names (the name or "" per wall id order).
// Collective in a distributed scene (the forces are summed over the ranks).
io::VtkPolyData wallsVtk(const sim::Simulation& s);

// Returns the contacts of the last step, a line per contact from element a's centre to element
// b's (to the contact point for a wall). Cell data: a, b (element ids; b -1 for a wall), wall
// (id or -1), force (on b), normal (a to b), normal_force (f.n, > 0 pushing apart),
// tangential_force (the rest of force), overlap. A distributed scene: the contacts this rank
// computed.
io::VtkPolyData contactsVtk(const sim::Simulation& s);

}  // namespace demlab::output
