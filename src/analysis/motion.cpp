#include "analysis/motion.hpp"

namespace demlab::analysis {

MotionResult meanMotion(const Sample& s, const Selection& sel) {
  MotionResult m;
  Vec3d momentum{};
  for (size_t i = 0; i < s.size(); ++i) {
    if (!selects(s, sel, i)) continue;
    ++m.elements;
    m.mass += s.mass[i];
    for (int k = 0; k < s.dim; ++k) momentum[k] += s.mass[i] * s.velocity[i][k];
  }
  if (m.elements == 0 || !(m.mass > 0)) return m;
  for (int k = 0; k < s.dim; ++k) m.velocity[k] = momentum[k] / m.mass;
  double twice = 0;  // sum m |v - <v>|^2
  for (size_t i = 0; i < s.size(); ++i) {
    if (!selects(s, sel, i)) continue;
    for (int k = 0; k < s.dim; ++k) {
      double u = s.velocity[i][k] - m.velocity[k];
      twice += s.mass[i] * u * u;
    }
  }
  m.fluctuationEnergy = 0.5 * twice;
  const double meanMass = m.mass / double(m.elements);
  m.temperature = twice / (double(s.dim) * double(m.elements) * meanMass);
  return m;
}

}  // namespace demlab::analysis
