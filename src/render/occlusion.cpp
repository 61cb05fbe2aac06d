#include "render/occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/interrupt.hpp"

namespace demlab::render {

namespace {

// Returns x as a cell index clamped to [lo, hi]; the clamp happens in double, before the
// conversion (a far grain's screen coordinate, or NaN, does not fit an int).
int cellIndex(double x, int lo, int hi) {
  if (!(x > lo)) return lo;
  if (!(x < hi)) return hi;
  return int(x);
}

}  // namespace

void cullHiddenGrains(const RenderScene& scene, const View& view, std::vector<std::uint32_t>& keep,
                      int cellSize) {
  const size_t n = scene.size();
  keep.clear();
  const double W = view.width, H = view.height;
  const double cs = std::max(double(cellSize), std::ceil(std::sqrt(W * H / 4e6)));
  const int gw = int(std::ceil(W / cs)), gh = int(std::ceil(H / cs));
  // Both arrays first touched in polled slices: tens of megabytes for half a million grains,
  // whose page faults alone were most of 77 ms without a poll on a VM.
  std::vector<float> occ =
      polledFill(size_t(gw) * gh, std::numeric_limits<float>::infinity(), "snapshot");
  const Eigen::Matrix3d R = view.view.topLeftCorner<3, 3>();
  const Vec3 T = view.view.topRightCorner<3, 1>();
  const double sx = view.proj(0, 0) * W / 2, sy = view.proj(1, 1) * H / 2;
  const bool ortho = view.orthographic;
  const double nearest = ortho ? -std::numeric_limits<double>::infinity() : view.near;

  // Per grain: its distance along the view axis (d) and its screen bounding box; d is NaN when
  // the grain reaches the near plane (never culled, never an occluder).
  struct Screen {
    double d, cx, cy, x0, x1, y0, y1;
  };
  std::vector<Screen> scr = polledFill(n, Screen{}, "snapshot");
  InterruptPoll poll("snapshot");
  for (size_t i = 0; i < n; ++i) {
    poll();
    const Vec3 e = R * (grainCentre(scene, i) - view.anchor) + T;
    const double r = scene.radii[i], d = -e.z();
    Screen& s = scr[i];
    if (d - r <= nearest) {
      s.d = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    s.d = d;
    if (ortho) {
      s.cx = W / 2 + sx * e.x();
      s.cy = H / 2 - sy * e.y();
      s.x0 = s.cx - sx * r;
      s.x1 = s.cx + sx * r;
      s.y0 = s.cy - sy * r;
      s.y1 = s.cy + sy * r;
    } else {
      s.cx = W / 2 + sx * e.x() / d;
      s.cy = H / 2 - sy * e.y() / d;
      // The sphere lies in the view-space box e +- r; its projection lies in the box spanned by
      // the projections of that box's corners, all in front of the eye here.
      const double xs[2] = {e.x() - r, e.x() + r}, ys[2] = {e.y() - r, e.y() + r},
                   ds[2] = {d - r, d + r};
      s.x0 = s.y0 = std::numeric_limits<double>::infinity();
      s.x1 = s.y1 = -std::numeric_limits<double>::infinity();
      for (double dd : ds)
        for (int k = 0; k < 2; ++k) {
          const double px = W / 2 + sx * xs[k] / dd, py = H / 2 - sy * ys[k] / dd;
          s.x0 = std::min(s.x0, px);
          s.x1 = std::max(s.x1, px);
          s.y0 = std::min(s.y0, py);
          s.y1 = std::max(s.y1, py);
        }
    }
    // Occluder: the cells wholly inside the centre-plane circle (radius rho on screen), row by
    // row, each row's span set by the circle's half-width at the row's edge farther from cy.
    const double rho = (ortho ? sy * r : sy * r / d);
    const int j0 = cellIndex(std::ceil((s.cy - rho) / cs), 0, gh);
    const int j1 = cellIndex(std::floor((s.cy + rho) / cs) - 1, -1, gh - 1);
    const float fd = float(d);
    for (int j = j0; j <= j1; ++j) {
      if (((j - j0) & 63) == 63) pollInterrupt("snapshot");
      const double dy = std::max(std::abs(j * cs - s.cy), std::abs((j + 1) * cs - s.cy));
      if (dy >= rho) continue;
      const double hw = std::sqrt(rho * rho - dy * dy);
      const int i0 = cellIndex(std::ceil((s.cx - hw) / cs), 0, gw);
      const int i1 = cellIndex(std::floor((s.cx + hw) / cs) - 1, -1, gw - 1);
      for (int k = i0; k <= i1; ++k) {
        float& o = occ[size_t(j) * gw + k];
        o = std::min(o, fd);
      }
    }
  }

  keep.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    poll();
    const Screen& s = scr[i];
    if (std::isnan(s.d)) {
      keep.push_back(std::uint32_t(i));
      continue;
    }
    if (s.x1 < 0 || s.y1 < 0 || s.x0 > W || s.y0 > H) continue;  // off the image
    const int i0 = cellIndex(std::floor(s.x0 / cs), 0, gw), i1 = cellIndex(s.x1 / cs, -1, gw - 1);
    const int j0 = cellIndex(std::floor(s.y0 / cs), 0, gh), j1 = cellIndex(s.y1 / cs, -1, gh - 1);
    // float occluder depths are compared with a relative margin, so rounding cannot hide a
    // grain that is level with its occluder.
    const double front = (s.d - scene.radii[i]) * (1 - 1e-5);
    bool hidden = true;
    for (int j = j0; j <= j1 && hidden; ++j) {
      if (((j - j0) & 63) == 63) pollInterrupt("snapshot");
      for (int k = i0; k <= i1; ++k)
        if (!(occ[size_t(j) * gw + k] < front)) {
          hidden = false;
          break;
        }
    }
    if (!hidden) keep.push_back(std::uint32_t(i));
  }
}

}  // namespace demlab::render
