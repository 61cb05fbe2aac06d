// SimulationManager<D>: sources and sinks (checking their Defs, adding, removing, reporting).
#include <algorithm>
#include <cmath>

#include "sim/convert.hpp"
#include "sim/simulation_manager.hpp"

namespace demlab::sim {

namespace {

// Throws {VALUE REGION} unless region is a usable region of dimension d, big enough for a ball of
// radius r (r = 0: any size). Changes nothing.
template <int D>
void checkRegion(const Region& region, Real r) {
  auto bad = [](const std::string& why) { throw Error("bad region: " + why, {"VALUE", "REGION"}); };
  const Vec3d* points[] = {&region.lo, &region.hi, &region.centre, &region.axis};
  for (const Vec3d* p : points) {
    for (double x : *p) {
      if (!std::isfinite(x)) bad("must be finite numbers");
    }
  }
  switch (region.kind) {
    case Region::Box:
      for (int k = 0; k < D; ++k) {
        if (!(region.hi[k] - region.lo[k] > 2 * r)) {
          bad(r > 0 ? "it is too small for the largest element" : "it is empty");
        }
      }
      break;
    case Region::Sphere:
      if (!(region.radius > r) || !std::isfinite(region.radius)) {
        bad(r > 0 ? "it is too small for the largest element" : "it is empty");
      }
      break;
    case Region::Cylinder: {
      if (D == 2) bad("a cylinder is a 3D region");
      double n = 0;
      for (double x : region.axis) n += x * x;
      if (std::abs(n - 1) > 1e-9) bad("the cylinder's axis must be a unit vector");
      if (!(region.radius > r) || !(region.halfLength > r) || !std::isfinite(region.radius) ||
          !std::isfinite(region.halfLength)) {
        bad(r > 0 ? "it is too small for the largest element" : "it is empty");
      }
      break;
    }
  }
}

// Throws {VALUE RADIUS} unless dist is a distribution a source can draw from (positive radii, a
// normal one cut above zero). Changes nothing.
void checkSizes(const SizeDistribution& dist) {
  const auto& p = dist.p;
  for (double x : p) {
    if (!std::isfinite(x)) throwBad("radius", physics::formatReal(x), "must be finite");
  }
  const bool ok = (dist.kind == "constant" && p.size() == 1 && p[0] > 0) ||
                  ((dist.kind == "uniform") && p.size() == 2 && p[0] > 0 && p[1] >= p[0]) ||
                  (dist.kind == "powerlaw" && p.size() == 3 && p[0] > 0 && p[1] >= p[0]) ||
                  (dist.kind == "normal" && p.size() == 2 && p[1] >= 0 && p[0] - 3 * p[1] > 0) ||
                  (dist.kind == "discrete" && p.size() >= 2 && p.size() % 2 == 0 &&
                   dist.maxRadius() > 0 && dist.minRadius() > 0);
  if (!ok) {
    throw Error("bad radius distribution \"" + dist.kind +
                    "\": radii must be positive (a normal one needs mean > 3 sd)",
                {"VALUE", "RADIUS"});
  }
}

// Throws {VALUE EVERY} unless 1 <= every <= kMaxBoundaryEvery.
void checkEvery(uint32_t every) {
  if (every < 1 || every > kMaxBoundaryEvery) {
    throwBad("every", std::to_string(every),
             "must be an integer in [1, " + std::to_string(kMaxBoundaryEvery) + "]");
  }
}

// Throws {VALUE NAME} or {EXISTS NAME} unless name is a valid name none of list has.
template <class List>
void checkNewName(const char* kind, const std::string& name, const List& list) {
  checkObjectName(kind, name);
  for (const auto& x : list) {
    if (x.def.name == name) throwNameExists(kind, name);
  }
}

// Removes the item of list whose Def is named name. Throws {LOOKUP NAME}, list unchanged.
template <class List>
void eraseNamed(List& list, const std::string& name, const char* kind) {
  const auto it =
      std::find_if(list.begin(), list.end(), [&](const auto& x) { return x.def.name == name; });
  if (it == list.end())
    throw Error("can't find " + std::string(kind) + " \"" + name + "\"", {"LOOKUP", "NAME"});
  list.erase(it);
}

std::string regionText(const Region& r) {
  switch (r.kind) {
    case Region::Box:
      return "box {" + formatVec(r.lo, 3) + "} {" + formatVec(r.hi, 3) + "}";
    case Region::Sphere:
      return "sphere {" + formatVec(r.centre, 3) + "} " + physics::formatReal(r.radius);
    case Region::Cylinder:
      return "cylinder {" + formatVec(r.centre, 3) + "} {" + formatVec(r.axis, 3) + "} " +
             physics::formatReal(r.radius) + " " + physics::formatReal(r.halfLength);
  }
  return "";
}

}  // namespace

template <int D>
void SimulationManager<D>::addSource(const SourceDef& def) {
  checkNewName("source", def.name, s_.sources);
  const uint32_t material = materialIndex(def.material);
  const bool byMass = def.massRate != 0, byCount = def.countRate != 0;
  if (byMass == byCount) {
    throw Error("bad rate: give exactly one of a mass rate and a number rate", {"VALUE", "RATE"});
  }
  if (!(std::isfinite(def.massRate) && def.massRate >= 0))
    throwBad("rate", physics::formatReal(def.massRate), "must be a positive number");
  if (!(std::isfinite(def.countRate) && def.countRate >= 0))
    throwBad("rate", physics::formatReal(def.countRate), "must be a positive number");
  if (!(std::isfinite(def.targetMass) && def.targetMass >= 0))
    throwBad("target", physics::formatReal(def.targetMass), "must be a non-negative number");
  checkSizes(def.size);
  checkRegion<D>(def.region, def.size.maxRadius());
  if (def.shape.empty()) {
    if (!def.shapeParams.empty()) {
      throw Error("bad shape parameters: a ball takes none (its size is -radius)",
                  {"VALUE", "SHAPE"});
    }
  } else {
    shapeParamsForBound(def.shape, def.shapeParams, 1);  // the shape itself, and scalable
  }
  const VecD<D> v = toVec<D>(def.velocity, "velocity");
  checkVelocityRange<D>(v);
  if (!(std::isfinite(def.jitter) && def.jitter >= 0))
    throwBad("jitter", physics::formatReal(def.jitter), "must be a non-negative number");
  // Every inserted velocity within the speed bound, checked here rather than when an element
  // is inserted mid-step (which would fail after the step had changed the scene).
  if (v.norm() + std::sqrt(double(D)) * def.jitter > validity::kMaxSpeed) {
    throwBad("jitter", physics::formatReal(def.jitter),
             "must keep every inserted speed within " + physics::formatReal(validity::kMaxSpeed) +
                 " m/s (|velocity| + sqrt(dimension) x jitter)");
  }
  if (!(def.tolerance >= 0 && def.tolerance < 1))
    throwBad("tolerance", physics::formatReal(def.tolerance), "must be in [0, 1)");
  if (def.tries < 1) throwBad("tries", std::to_string(def.tries), "must be at least 1");
  checkEvery(def.every);
  for (const std::string& t : def.tags) checkTagName(t);
  SourceState src;
  src.def = def;
  src.material = material;
  src.start = s_.time;
  src.rng = def.seed;
  s_.sources.push_back(std::move(src));
  touchConfig();
}

template <int D>
void SimulationManager<D>::removeSource(const std::string& name) {
  eraseNamed(s_.sources, name, "source");
  touchConfig();
}

template <int D>
std::vector<BoundaryInfo> SimulationManager<D>::sources() const {
  std::vector<BoundaryInfo> out;
  for (const SourceState& s : s_.sources) {
    const SourceDef& d = s.def;
    const std::string rate = d.massRate > 0 ? physics::formatReal(d.massRate) + " kg/s"
                                            : physics::formatReal(d.countRate) + " /s";
    out.push_back(
        {d.name, "source into " + regionText(d.region) + " at " + rate, s.count, s.mass, s.start});
  }
  return out;
}

template <int D>
void SimulationManager<D>::addSink(const SinkDef& def) {
  checkNewName("sink", def.name, s_.sinks);
  checkEvery(def.every);
  SinkDef d = def;
  if (d.kind == SinkDef::Plane) {
    toVec<D>(d.point, "point");
    VecD<D> n = toVec<D>(d.normal, "normal");
    if (!(n.norm() > 0)) throwBad("normal", formatVec(d.normal, D), "must be a non-zero vector");
    n.normalize();
    d.normal = fromVec<D>(n);
  } else {
    checkRegion<D>(d.region, 0);
  }
  SinkState k;
  k.def = d;
  k.start = s_.time;
  s_.sinks.push_back(std::move(k));
  touchConfig();
}

template <int D>
void SimulationManager<D>::removeSink(const std::string& name) {
  eraseNamed(s_.sinks, name, "sink");
  touchConfig();
}

template <int D>
std::vector<BoundaryInfo> SimulationManager<D>::sinks() const {
  std::vector<BoundaryInfo> out;
  for (const SinkState& k : s_.sinks) {
    const SinkDef& d = k.def;
    const std::string where =
        d.kind == SinkDef::Plane
            ? "beyond the plane through {" + formatVec(d.point, D) + "} normal {" +
                  formatVec(d.normal, D) + "}"
            : std::string(d.outside ? "outside " : "inside ") + regionText(d.region);
    out.push_back({d.name, "sink " + where, k.count, k.mass, k.start});
  }
  return out;
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
