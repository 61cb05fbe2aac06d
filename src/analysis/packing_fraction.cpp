#include "analysis/packing_fraction.hpp"

#include "analysis/region_geometry.hpp"

namespace demlab::analysis {

PackingResult packing(const Sample& s, const Selection& sel, const Region& region) {
  PackingResult p;
  const int d = s.dim;
  p.volume = region.volume(d);
  for (size_t i = 0; i < s.size(); ++i) {
    if (!sel.hasTag(i)) continue;
    const double r = s.radius[i];
    double inside = ballVolumeInside(region, s.position[i], r, d);
    if (!s.ball[i]) {
      // The bounding ball: wholly inside, wholly outside, or across (not counted).
      if (region.holds(s.position[i], r, d)) {
        inside = s.volume[i];
      } else if (inside > 0) {
        p.straddling = int64_t(i);
        return p;
      }
    }
    if (inside <= 0) continue;
    ++p.elements;
    p.solid += inside;
    p.mass += s.mass[i] * inside / s.volume[i];
  }
  p.fraction = p.solid / p.volume;
  return p;
}

}  // namespace demlab::analysis
