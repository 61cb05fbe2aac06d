// Sample: what the analysis queries read of a scene, copied into plain arrays (dense order),
// and Selection: which elements and which parts of the contacts a query counts (a tag, a
// region, or both). The queries work on a Sample, never on the Simulation, so they can be
// tested on hand-made data and never change the scene.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/packing.hpp"
#include "sim/simulation.hpp"

namespace demlab::analysis {

using sim::Region;
using sim::Vec3d;

// One contact of the last step: element a with element b, or with a wall (b < 0).
struct SampleContact {
  uint32_t a = 0;
  int64_t b = -1;     // dense index of the other element; -1: a wall
  int64_t wall = -1;  // the wall's slot (its handle's index); -1: an element
  Vec3d point{}, normal{};  // normal from a towards b (or the wall)
  Vec3d force{};            // on b (or the wall); a receives its opposite
};

struct Sample {
  int dim = 3;
  std::vector<sim::ElementId> ids;
  std::vector<Vec3d> position, velocity;
  std::vector<double> radius, mass, volume;  // volume: area in 2D
  std::vector<char> ball;                    // 1 for a ball (sphere or disc)
  std::vector<SampleContact> contacts;       // the records' order
  // The intact bonds, when gathered: the point midway between the surfaces on the line of
  // centres, the bond's force on b. Apart from the contacts: a bond is not a contact.
  std::vector<SampleContact> bonds;
  // The scene's periodic cell: an arm's branch is measured to the nearest image.
  sim::PeriodicDef periodic;
  size_t size() const { return ids.size(); }
};

// Returns the elements and the last step's contacts of sim (a volume is mass / density for an
// element that is not a ball), and with withBonds its intact bonds. Changes nothing. A
// distributed scene: the whole scene's, gathered on every rank (collective), its elements in
// the order of their ids.
Sample gatherSample(const sim::Simulation& sim, bool withBonds = false);

// One side of a contact seen from one of its elements: the force on that element, applied at
// the contact point, and the branch from the element's centre to that point. A grain pair has
// two arms, a wall contact one (the element's).
struct Arm {
  uint32_t element;
  Vec3d force;   // on the element
  Vec3d branch;  // contact point - the element's centre
};

// Returns the arms of contact c. Changes nothing.
std::vector<Arm> armsOf(const Sample& s, const SampleContact& c);

// Which elements a query counts: those carrying a tag (tagged empty: all), and of those the
// ones whose centre is in the region (when one is given). A contact arm counts by the fraction
// of its branch inside the region (see armWeight).
struct Selection {
  std::vector<char> tagged;  // per element; empty: every element
  std::optional<Region> region;
  bool hasTag(size_t i) const { return tagged.empty() || tagged[i]; }
};

// Returns true if element i is counted (its tag, and its centre inside the region).
bool selects(const Sample& s, const Selection& sel, size_t i);

// Returns the weight (0 to 1) of arm a: 0 unless its element carries the tag, else the
// fraction of its branch (centre to contact point) inside the region (1 with no region).
double armWeight(const Sample& s, const Selection& sel, const Arm& a);

// Returns the number of elements selects() counts. Changes nothing.
size_t selectedCount(const Sample& s, const Selection& sel);

// Returns the contacts in the records' order with the repeated records of one pair (shape
// elements touch at several points) counted once: per record, true if it is the first of its
// pair. Changes nothing.
std::vector<char> firstOfPair(const Sample& s);

}  // namespace demlab::analysis
