#include "analysis/structure.hpp"

#include <cmath>

namespace demlab::analysis {

namespace {

// Returns |x| over the first d axes.
double length(const Vec3d& x, int d) {
  double s = 0;
  for (int k = 0; k < d; ++k) s += x[k] * x[k];
  return std::sqrt(s);
}

}  // namespace

Coordination coordination(const Sample& s, const Selection& sel, bool walls) {
  std::vector<size_t> count(s.size(), 0);
  const std::vector<char> first = firstOfPair(s);
  for (size_t k = 0; k < s.contacts.size(); ++k) {
    const SampleContact& c = s.contacts[k];
    if (!first[k] || (c.b < 0 && !walls)) continue;
    ++count[c.a];
    if (c.b >= 0) ++count[size_t(c.b)];
  }
  Coordination z;
  for (size_t i = 0; i < s.size(); ++i) {
    if (!selects(s, sel, i)) continue;
    ++z.elements;
    z.ends += count[i];
    z.rattlers0 += count[i] == 0;
    z.rattlers1 += count[i] == 1;
  }
  if (z.elements == 0) return z;
  z.plain = double(z.ends) / double(z.elements);
  size_t kept = z.elements - z.rattlers0 - z.rattlers1;
  if (kept > 0) z.mechanical = double(z.ends - z.rattlers1) / double(kept);
  return z;
}

Fabric fabric(const Sample& s, const Selection& sel, bool walls) {
  Fabric f;
  for (const SampleContact& c : s.contacts) {
    if (c.b < 0 && !walls) continue;
    double held = 0, total = 0;  // lengths of the arms: held by the selection, and in all
    for (const Arm& a : armsOf(s, c)) {
      double l = length(a.branch, s.dim);
      held += l * armWeight(s, sel, a);
      total += l;
    }
    double w = total > 0 ? held / total : 0;
    if (w == 0) continue;
    addScaled(f.tensor, outer(c.normal, c.normal), w);
    f.contacts += w;
  }
  if (f.contacts > 0)
    for (double& x : f.tensor) x /= f.contacts;
  return f;
}

}  // namespace demlab::analysis
