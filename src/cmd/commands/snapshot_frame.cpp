#include "cmd/commands/snapshot_frame.hpp"
#include "physics/triangle_mesh.hpp"

#ifdef DEMLAB_HAVE_RENDER

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <memory>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include "cmd/commands/snapshot_contacts.hpp"
#include "core/background_work.hpp"
#include "core/interrupt.hpp"
#include "render/colour_map.hpp"
#include "render/image_file.hpp"
#include "render/layout.hpp"
#include "render/pick.hpp"
#include "render/renderer.hpp"
#include "render/view.hpp"

namespace demlab::cmd {
namespace {

using render::RenderWall;

// Returns nothing; keeps the rows (of `width` entries each) of v whose keep flag is set, in
// order. An empty v stays empty. Changes v.
template <class T>
void compactRows(std::vector<T>& v, size_t width, const std::vector<char>& keep) {
  if (v.empty()) return;
  size_t out = 0;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    for (size_t k = 0; k < width; ++k) v[out * width + k] = v[i * width + k];
    ++out;
  }
  v.resize(out * width);
}

// The process's one renderer (an OSMesa context), made on first use and kept: a context costs
// tens of milliseconds, a frame of a small scene less. It is never destroyed: from an exit
// handler, destroying the context can wait for ever on software GL's threads, which the exit
// may already have stopped (the process's memory goes back to the system anyway).
// It is made on a thread of its own while the command polls Ctrl-C: the context and its
// shaders are made in calls that cannot be interrupted (0.1 s, 0.3 s under the sanitizers). A
// command stopped meanwhile leaves it being made for the next; a failure to make it is raised
// by the command waiting and the next one tries again. Throws demlab::Error {INTERRUPTED}.
render::Renderer& theRenderer() {
  // Set by the thread that makes it, so that a renderer made after its command was stopped is
  // held by this static pointer and not only by the future's state, which the exit frees.
  static std::atomic<render::Renderer*> made{nullptr};
  static std::shared_future<void> making;
  if (render::Renderer* r = made.load()) return *r;
  if (!making.valid()) {
    std::promise<void> done;
    making = done.get_future().share();
    // Counted from before the thread starts: an exit waits for it (core/background_work.hpp).
    std::thread([done = std::move(done), work = std::make_unique<BackgroundWork>()]() mutable {
      try {
        made.store(render::makeRenderer().release());
        done.set_value();
      } catch (...) {
        done.set_exception(std::current_exception());
      }
    }).detach();
  }
  while (making.wait_for(std::chrono::milliseconds(5)) != std::future_status::ready)
    pollInterrupt("snapshot");
  try {
    making.get();
  } catch (...) {
    making = {};
    throw;
  }
  return *made.load();
}

Vec3 v3(const sim::Vec3d& a) {
  return Vec3(a[0], a[1], a[2]);
}

// Returns the walls of s as the renderer draws them.
std::vector<RenderWall> renderWalls(const sim::Simulation& s) {
  std::vector<RenderWall> out;
  const int d = s.dim();
  for (sim::WallId id : s.wallIds()) {
    const sim::WallState w = s.wall(id);
    const Vec3 c = v3(w.centre), a0 = v3(w.axes[0]), a1 = v3(w.axes[1]), a2 = v3(w.axes[2]);
    const Vec3 h = v3(w.halfExtents);
    switch (w.shape) {
      case sim::WallShape::Plane:
        out.push_back(RenderWall::plane(c, v3(w.normal)));
        break;
      case sim::WallShape::Finite:
        if (d == 2 && w.hole > 0) {
          // A slot: the two segments either side of the gap.
          out.push_back(RenderWall::segment(c - h[0] * a0, c - w.hole * a0));
          out.push_back(RenderWall::segment(c + w.hole * a0, c + h[0] * a0));
        } else if (d == 2) {
          out.push_back(RenderWall::segment(c - h[0] * a0, c + h[0] * a0));
        } else {
          out.push_back(
              RenderWall::rectangle(c - h[0] * a0 - h[1] * a1, 2 * h[0] * a0, 2 * h[1] * a1));
          out.back().radius = w.hole;
        }
        break;
      case sim::WallShape::Box:
        if (d == 2) {
          out.push_back(
              RenderWall::rectangle(c - h[0] * a0 - h[1] * a1, 2 * h[0] * a0, 2 * h[1] * a1));
        } else if ((a0 - Vec3::UnitX()).norm() < 1e-12 && (a1 - Vec3::UnitY()).norm() < 1e-12) {
          out.push_back(RenderWall::box(c - h, c + h));
        } else {
          // A turned box: its six faces.
          const Vec3 e[3] = {h[0] * a0, h[1] * a1, h[2] * a2};
          for (int k = 0; k < 3; ++k) {
            const Vec3 &u = e[(k + 1) % 3], &v = e[(k + 2) % 3];
            for (int sgn : {-1, 1})
              out.push_back(RenderWall::rectangle(c + sgn * e[k] - u - v, 2 * u, 2 * v));
          }
        }
        break;
      case sim::WallShape::Drum:
        out.push_back(RenderWall::drum(c, d == 2 ? Vec3::UnitZ() : a0, w.radius,
                                       d == 2 ? 0.0 : 2 * w.halfLength));
        break;
      case sim::WallShape::Mesh: {
        const physics::TriangleMesh& m = *w.mesh;
        Mat3 R;
        R << a0, a1, a2;
        for (const auto& t : m.triangles) {
          out.push_back(RenderWall::triangle(c + R * m.vertices[t[0]], c + R * m.vertices[t[1]],
                                             c + R * m.vertices[t[2]]));
        }
        break;
      }
    }
  }
  return out;
}

// The arrays a RenderScene views; they must outlive the render call.
struct FrameData {
  std::vector<double> centres, radii, field, angles, orientations;
  std::vector<float> colours;
  std::vector<int32_t> meshOf;
  std::vector<render::ChainLink> chains;
  std::vector<std::int64_t> ids;  // script ids, filled only for picking and highlighting
  render::RenderScene scene;
};

// Returns the legend's name of field by.
std::string fieldTitle(const std::string& by) {
  if (by == "force") return "net force";
  if (by == "contactforce") return "contact force";
  return by;
}

// Returns nothing; keeps in f only the grains o draws (those with one of o.tags, those on the
// kept side of o.clip) and the chains between two of them. Changes f's per-grain arrays.
void keepDrawn(const sim::Simulation& s, const SnapOptions& o, FrameData& f) {
  const size_t n = f.radii.size();
  const int d = s.dim();
  std::vector<char> keep(n, 1);
  if (!o.tags.empty()) {
    std::fill(keep.begin(), keep.end(), 0);
    for (const std::string& t : o.tags)
      for (uint32_t i : s.taggedIndices(t)) keep[i] = 1;
  }
  if (o.clip) {
    const auto& c = *o.clip;
    for (size_t i = 0; i < n; ++i) {
      double side = 0;
      for (int k = 0; k < d; ++k)
        side += (f.centres[i * size_t(d) + size_t(k)] - c[size_t(k)]) * c[size_t(3 + k)];
      if (side > 0) keep[i] = 0;
    }
  }
  if (std::all_of(keep.begin(), keep.end(), [](char k) { return k != 0; })) return;
  std::erase_if(f.chains, [&](const render::ChainLink& l) { return !keep[l.a] || !keep[l.b]; });
  std::vector<std::uint32_t> renumber(n);
  for (size_t i = 0, m = 0; i < n; ++i) renumber[i] = std::uint32_t(keep[i] ? m++ : m);
  for (render::ChainLink& l : f.chains) l.a = renumber[l.a], l.b = renumber[l.b];
  compactRows(f.centres, size_t(d), keep);
  compactRows(f.radii, 1, keep);
  compactRows(f.field, 1, keep);
  compactRows(f.colours, 3, keep);
  compactRows(f.angles, 1, keep);
  compactRows(f.orientations, 4, keep);
  compactRows(f.meshOf, 1, keep);
  compactRows(f.ids, 1, keep);
}

// Returns nothing; sets the series' fixed framing, legend width and colour range in sc and r,
// fixing each from this frame when not yet fixed: the framing and legend width when o asks for
// a fixed camera, the range when o asks for -range first and this frame's field has a spread.
// Changes sc, r and lock.
void applySeriesLock(const SnapOptions& o, render::RenderScene& sc, render::RenderOptions& r,
                     SeriesLock& lock) {
  if (o.cameraFixed && !o.camera) {
    if (!lock.bounds) {
      const render::Bounds b = render::sceneBounds(sc);
      lock.bounds = {b.lo.x(), b.lo.y(), b.lo.z(), b.hi.x(), b.hi.y(), b.hi.z()};
    }
    const auto& b = *lock.bounds;
    sc.bounds.lo = Vec3(b[0], b[1], b[2]);
    sc.bounds.hi = Vec3(b[3], b[4], b[5]);
  }
  if (o.rangeFirst && !sc.field.empty() && r.colourMap != render::ColourMap::categorical) {
    if (!lock.range) {
      const auto [lo, hi] = std::minmax_element(sc.field.begin(), sc.field.end());
      if (*hi > *lo) lock.range = std::array<double, 2>{*lo, *hi};
    }
    if (lock.range) {
      r.fieldMin = (*lock.range)[0];
      r.fieldMax = (*lock.range)[1];
    }
  }
  if (o.cameraFixed) {
    // Kept after the range: the first frame's strip is measured with its own labels.
    if (!lock.legendWidth)
      lock.legendWidth = render::frameLayout(sc, r, render::defaultTypeface()).legend.width();
    r.legendWidth = *lock.legendWidth;
  }
}

// Throws {MPI UNSUPPORTED} on every rank for what a distributed scene's frame cannot draw yet:
// force chains and contact forces (a contact's ends on two ranks), per-element -color values.
void refuseOnRanks(const SnapOptions& o) {
  const char* what = o.chains                       ? "-chains"
                     : o.colourBy == "contactforce" ? "-color contactforce"
                     : o.colourBy == "value"        ? "-color value"
                                                    : nullptr;
  if (what != nullptr) {
    throw Error(std::string("snapshots of a distributed scene can't draw ") + what + " yet",
                {"MPI", "UNSUPPORTED"});
  }
}

// Returns nothing; keeps in f this rank's own elements (the arrays are read with the ghosts
// after them). Changes f's per-grain arrays.
void keepOwned(const sim::Simulation& s, FrameData& f) {
  const size_t n = s.distribution().owned, d = size_t(s.dim());
  const auto cut = [&](auto& v, size_t per) {
    if (v.size() > n * per) v.resize(n * per);
  };
  cut(f.centres, d), cut(f.radii, 1), cut(f.field, 1), cut(f.colours, 3), cut(f.ids, 1);
  cut(f.angles, 1), cut(f.orientations, 4), cut(f.meshOf, 1);
}

// Returns nothing; replaces f's per-grain arrays by every rank's, one rank after another
// (collective): each rank renders nothing but rank 0, which draws the whole scene.
void gatherDrawn(const sim::Simulation& s, FrameData& f) {
  std::vector<char> mine;
  const auto put = [&](const auto& v) {
    const uint64_t bytes = v.size() * sizeof(v[0]);
    const size_t at = mine.size();
    mine.resize(at + sizeof bytes + bytes);
    std::memcpy(mine.data() + at, &bytes, sizeof bytes);
    if (bytes > 0) std::memcpy(mine.data() + at + sizeof bytes, v.data(), bytes);
  };
  put(f.centres), put(f.radii), put(f.field), put(f.colours), put(f.ids);
  const std::vector<std::vector<char>> all = ranksOf(s).gatherBytes(mine);
  f.centres.clear(), f.radii.clear(), f.field.clear(), f.colours.clear(), f.ids.clear();
  for (const std::vector<char>& b : all) {
    size_t at = 0;
    const auto take = [&](auto& v) {
      uint64_t bytes = 0;
      std::memcpy(&bytes, b.data() + at, sizeof bytes);
      at += sizeof bytes;
      const size_t old = v.size();
      v.resize(old + bytes / sizeof(v[0]));
      if (bytes > 0) std::memcpy(v.data() + old, b.data() + at, bytes);
      at += bytes;
    };
    take(f.centres), take(f.radii), take(f.field), take(f.colours), take(f.ids);
  }
}

// Returns the frame of s as o asks (the scene part), with the drawn elements' script ids when
// withIds. Reads the scene only; collective in a distributed scene (every rank's elements).
void buildFrame(const sim::Simulation& s, const SnapOptions& o, FrameData& f,
                bool withIds = false) {
  // Ctrl-C between the gathers (each a copy of an array of the scene: tens of milliseconds at
  // half a million grains, most of it page faults); a pure read, so any poll may stop it.
  const auto poll = [] { pollInterrupt("snapshot"); };
  const int d = s.dim();
  f.centres = s.positions();
  poll();
  // (A distributed scene's elements by the ids scripts know.)
  const auto idOf = [&](sim::ElementId id) {
    return scriptId(s.distributed() ? s.originalHandle(id) : id);
  };
  if (s.distributed()) refuseOnRanks(o);
  if (withIds || !o.highlight.empty())
    for (sim::ElementId id : s.elementIds()) f.ids.push_back(idOf(id));
  f.radii = s.radii();
  poll();
  const std::size_t n = f.radii.size();
  render::RenderScene& sc = f.scene;
  sc.dim = d;
  sc.categoryNames.clear();
  if (d == 2) f.angles = s.orientations();
  const std::string& by = o.colourBy;
  // Element ids to dense indices, built only for what needs them (a hash map of every element).
  const bool needsDense = by == "contactforce" || o.chains;
  const DenseIndex dense = needsDense ? denseIndex(s) : DenseIndex{};
  auto norms = [&](const std::vector<double>& v, int k) {
    f.field.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      double q = 0;
      for (int j = 0; j < k; ++j)
        q += v[i * std::size_t(k) + std::size_t(j)] * v[i * std::size_t(k) + std::size_t(j)];
      f.field[i] = std::sqrt(q);
    }
  };
  if (o.fixed) {
    f.colours.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) f.colours[3 * i + std::size_t(k)] = (*o.fixed)[std::size_t(k)];
    f.field.clear();
  } else if (by == "speed") {
    norms(s.velocities(), d);
  } else if (by == "force") {
    norms(s.forces(), d);
  } else if (by == "contactforce") {
    f.field = contactForceSums(s, dense);
  } else if (by == "spin") {
    norms(s.angularVelocities(), d == 2 ? 1 : 3);
  } else if (by == "radius") {
    f.field = f.radii;
  } else if (by == "value") {
    f.field = o.values;
  } else if (by == "id") {
    f.field.clear();
    for (sim::ElementId id : s.elementIds()) f.field.push_back(double(idOf(id)));
  } else if (by == "material") {
    const auto names = s.materialNames();
    f.field.clear();
    for (sim::ElementId id : s.elementIds()) {
      const std::string m = s.element(id).material;
      f.field.push_back(double(std::find(names.begin(), names.end(), m) - names.begin()));
    }
    sc.categoryNames = names;
  } else {  // tag: the first of o.tags a grain carries (only those grains are drawn)
    f.field.assign(n, double(o.tags.size()));
    for (std::size_t k = o.tags.size(); k-- > 0;)
      for (uint32_t i : s.taggedIndices(o.tags[k])) f.field[i] = double(k);
    sc.categoryNames = o.tags;
  }
  poll();
  // Elements of shapes with a render row are drawn as their meshes.
  sim::Simulation::ElementMeshes m = s.elementMeshes();
  f.meshOf = std::move(m.meshOf);
  sc.meshes.clear();
  for (const auto& mesh : m.meshes) {
    sc.meshes.emplace_back();
    for (const sim::Vec3d& p : mesh) sc.meshes.back().push_back(Vec3(p[0], p[1], p[2]));
  }
  if (!f.meshOf.empty() && d == 3) f.orientations = s.orientations();
  if (o.chains) f.chains = forceChains(s, dense, o.chainMin);
  poll();
  if (s.distributed()) keepOwned(s, f);
  keepDrawn(s, o, f);
  if (s.distributed()) gatherDrawn(s, f);
  poll();
  sc.centres = f.centres;
  sc.radii = f.radii;
  sc.colours = o.fixed ? std::span<const float>(f.colours) : std::span<const float>();
  sc.field = o.fixed ? std::span<const double>() : std::span<const double>(f.field);
  sc.fieldName = o.fixed ? "" : fieldTitle(by);
  sc.fieldUnit = o.fixed ? "" : by == "value" ? o.valueUnit : fieldUnit(by);
  sc.title = o.title;
  sc.chains = f.chains;
  sc.highlighted.clear();
  if (!o.highlight.empty()) {
    const std::unordered_set<std::int64_t> marked(o.highlight.begin(), o.highlight.end());
    for (size_t i = 0; i < f.ids.size(); ++i)
      if (marked.count(f.ids[i])) sc.highlighted.push_back(std::uint32_t(i));
  }
  sc.angles = d == 2 ? std::span<const double>(f.angles) : std::span<const double>();
  if (o.walls) sc.walls = renderWalls(s);
  sc.meshOf = f.meshOf;
  sc.orientations = d == 3 ? std::span<const double>(f.orientations) : std::span<const double>();
  sc.time = o.timeStamp ? s.time() : std::numeric_limits<double>::quiet_NaN();
}

render::RenderOptions renderOptions(const SnapOptions& o) {
  render::RenderOptions r;
  r.width = o.width;
  r.height = o.height;
  r.background = o.background;
  r.camera.automatic = !o.camera;
  r.camera.position = v3(o.position);
  r.camera.lookAt = v3(o.lookAt);
  r.camera.up = v3(o.up);
  r.camera.fov = o.fov;
  r.camera.orthographic = o.ortho;
  r.camera.viewHeight = o.viewHeight;
  const bool categorical = o.colourBy == "id" || o.colourBy == "material" || o.colourBy == "tag";
  r.colourMap = render::colourMapNamed(
      o.colourMap.empty() ? (categorical ? "categorical" : "viridis") : o.colourMap);
  if (o.range) {
    r.fieldMin = (*o.range)[0];
    r.fieldMax = (*o.range)[1];
  }
  r.legend = o.legend;
  r.timeStamp = o.timeStamp;
  r.antialias = o.antialias;
  return r;
}

}  // namespace

void writeFrame(const sim::Simulation& s, const SnapOptions& o, const std::string& path,
                SeriesLock* lock) {
  FrameData f;
  buildFrame(s, o, f);
  // A distributed scene: rank 0 draws the gathered elements; an error there is every rank's.
  togetherOnRanks(s, [&] {
    if (ranksOf(s).rank() != 0) return;
    render::RenderOptions r = renderOptions(o);
    if (lock) applySeriesLock(o, f.scene, r, *lock);
    const render::Image img = theRenderer().render(f.scene, r);
    render::writeImage(img, path, o.jpeg ? render::ImageFormat::jpeg : render::ImageFormat::png,
                       o.quality);
  });
}

render::Image renderFrame(const sim::Simulation& s, const SnapOptions& o) {
  FrameData f;
  buildFrame(s, o, f);
  return theRenderer().render(f.scene, renderOptions(o));
}

std::int64_t pickFrame(const sim::Simulation& s, const SnapOptions& o, int x, int y) {
  FrameData f;
  buildFrame(s, o, f, true);
  const long i = render::pickGrain(f.scene, renderOptions(o), x, y);
  return i < 0 ? -1 : f.ids[size_t(i)];
}

FrameCamera frameCamera(const sim::Simulation& s, const SnapOptions& o) {
  FrameData f;
  buildFrame(s, o, f);
  const render::RenderOptions r = renderOptions(o);
  render::checkScene(f.scene);
  render::checkOptions(r);
  const render::View v = render::frameView(f.scene, r).view;
  FrameCamera c;
  for (int k = 0; k < 3; ++k) {
    c.position[size_t(k)] = v.eye[k];
    c.lookAt[size_t(k)] = v.anchor[k];
    c.up[size_t(k)] = v.view(1, k);  // the view's second row: the camera's up in the world
  }
  c.orthographic = v.orthographic;
  c.fov = o.fov;
  c.viewHeight = 2 / v.proj(1, 1);
  return c;
}

}  // namespace demlab::cmd

#endif  // DEMLAB_HAVE_RENDER
