#include "cmd/commands/snapshot_contacts.hpp"

#ifdef DEMLAB_HAVE_RENDER

#include <cmath>

namespace demlab::cmd {
namespace {

// Returns the length of v.
double magnitude(const sim::Vec3d& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

DenseIndex denseIndex(const sim::Simulation& s) {
  DenseIndex dense;
  const auto ids = s.elementIds();
  for (std::size_t i = 0; i < ids.size(); ++i) dense[ids[i].bits()] = i;
  return dense;
}

std::vector<double> contactForceSums(const sim::Simulation& s, const DenseIndex& dense) {
  std::vector<double> sums(s.elementCount(), 0.0);
  for (const sim::ContactInfo& c : s.contacts()) {
    const double f = magnitude(c.force);
    sums[dense.at(c.a.bits())] += f;
    if (!c.b.isNull()) sums[dense.at(c.b.bits())] += f;
  }
  return sums;
}

std::vector<render::ChainLink> forceChains(const sim::Simulation& s, const DenseIndex& dense,
                                           double minFraction) {
  std::vector<render::ChainLink> links;
  double total = 0;
  for (const sim::ContactInfo& c : s.contacts()) {
    if (c.b.isNull()) continue;
    const double f = magnitude(c.force);
    links.push_back({std::uint32_t(dense.at(c.a.bits())), std::uint32_t(dense.at(c.b.bits())), f});
    total += f;
  }
  if (links.empty()) return links;
  const double cut = minFraction * total / double(links.size());
  std::erase_if(links, [&](const render::ChainLink& l) { return !(l.force > cut); });
  return links;
}

}  // namespace demlab::cmd

#endif  // DEMLAB_HAVE_RENDER
