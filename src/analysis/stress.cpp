#include "analysis/stress.hpp"

#include "analysis/motion.hpp"

namespace demlab::analysis {

StressResult loveWeberStress(const Sample& s, const Selection& sel, double volume) {
  StressResult out;
  out.volume = volume;
  // Returns the summed arm weights of pairs, whose stress it adds to into.
  const auto sum = [&](const std::vector<SampleContact>& pairs, Tensor& into) {
    double arms = 0;
    for (const SampleContact& c : pairs) {
      for (const Arm& a : armsOf(s, c)) {
        double w = armWeight(s, sel, a);
        if (w == 0) continue;
        // The force on the element is the opposite of what it exerts: -f (x) l is the arm's
        // compression-positive moment.
        addScaled(into, outer(a.force, a.branch), -w / volume);
        arms += w;
      }
    }
    return arms;
  };
  out.arms = sum(s.contacts, out.contact);  // the contacts' alone, as StressResult says
  sum(s.bonds, out.bond);
  const MotionResult m = meanMotion(s, sel);
  out.elements = m.elements;
  for (size_t i = 0; i < s.size(); ++i) {
    if (!selects(s, sel, i)) continue;
    Vec3d u{};
    for (int k = 0; k < s.dim; ++k) u[k] = s.velocity[i][k] - m.velocity[k];
    addScaled(out.kinetic, outer(u, u), s.mass[i] / volume);
  }
  return out;
}

}  // namespace demlab::analysis
