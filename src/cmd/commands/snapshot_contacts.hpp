// What snapshots read from the scene's contacts: the contact-force magnitude of each grain and
// the force chains between grains.
#pragma once

#ifdef DEMLAB_HAVE_RENDER

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "cmd/commands/commands.hpp"
#include "render/scene.hpp"

namespace demlab::cmd {

// Element handle bits -> dense index (the order of the bulk getters).
using DenseIndex = std::unordered_map<std::uint64_t, std::size_t>;

// Returns the dense index of every element of s.
DenseIndex denseIndex(const sim::Simulation& s);

// Returns, per grain in dense order, the sum of |force| over its contacts of the last step
// (grains and walls): what a grain carries, large in a static bed where the net force is ~0.
std::vector<double> contactForceSums(const sim::Simulation& s, const DenseIndex& dense);

// Returns the grain-grain contacts of the last step whose |force| exceeds minFraction x the
// mean |force| of those contacts, as links between dense indices.
std::vector<render::ChainLink> forceChains(const sim::Simulation& s, const DenseIndex& dense,
                                           double minFraction);

}  // namespace demlab::cmd

#endif  // DEMLAB_HAVE_RENDER
