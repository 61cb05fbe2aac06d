// The checks run before any rendering (scene.hpp), and the RenderWall makers.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "render/scene.hpp"

namespace demlab::render {

RenderWall RenderWall::plane(const Vec3& point, const Vec3& normal) {
  RenderWall w;
  w.kind = WallKind::plane;
  w.p = {point, normal, Vec3::Zero()};
  return w;
}

RenderWall RenderWall::segment(const Vec3& a, const Vec3& b) {
  RenderWall w;
  w.kind = WallKind::segment;
  w.p = {a, b, Vec3::Zero()};
  return w;
}

RenderWall RenderWall::rectangle(const Vec3& corner, const Vec3& u, const Vec3& v) {
  RenderWall w;
  w.kind = WallKind::rectangle;
  w.p = {corner, u, v};
  return w;
}

RenderWall RenderWall::box(const Vec3& lo, const Vec3& hi) {
  RenderWall w;
  w.kind = WallKind::box;
  w.p = {lo, hi, Vec3::Zero()};
  return w;
}

RenderWall RenderWall::drum(const Vec3& centre, const Vec3& axis, double radius, double length) {
  RenderWall w;
  w.kind = WallKind::drum;
  w.p = {centre, axis, Vec3::Zero()};
  w.radius = radius;
  w.length = length;
  return w;
}

RenderWall RenderWall::triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  RenderWall w;
  w.kind = WallKind::triangle;
  w.p = {a, b, c};
  return w;
}

namespace {

// Returns v formatted the way Tcl prints a double.
std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::string indexed(const char* what, size_t i) {
  return std::string(what) + " " + std::to_string(i);
}

bool finite3(const Vec3& v) {
  return v.allFinite();
}

bool unitColour(const Rgb& c) {
  for (float x : c)
    if (!(x >= 0 && x <= 1)) return false;
  return true;
}

void checkLength(const char* what, size_t got, size_t want) {
  if (got != want)
    throw Error("bad " + std::string(what) + " array: " + std::to_string(got) +
                    " numbers, must be " + std::to_string(want),
                {"VALUE", "LENGTH"});
}

void checkWall(const RenderWall& w, size_t i, int dim) {
  auto bad = [&](const std::string& why) {
    return Error("bad " + indexed("wall", i) + ": " + why, {"VALUE", "WALL"});
  };
  for (const Vec3& q : w.p)
    if (!finite3(q)) throw bad("coordinate is not a finite number");
  if (!unitColour(w.colour)) throw bad("colour components must be numbers from 0 to 1");
  auto planar = [&](const Vec3& v) { return dim == 2 ? Vec3(v.x(), v.y(), 0) : v; };
  switch (w.kind) {
    case WallKind::plane:
      if (planar(w.p[1]).squaredNorm() == 0) throw bad("normal must be a nonzero vector");
      break;
    case WallKind::segment:
      if (planar(w.p[1] - w.p[0]).squaredNorm() == 0) throw bad("ends must differ");
      break;
    case WallKind::rectangle: {
      const Vec3 u = planar(w.p[1]), v = planar(w.p[2]);
      if (dim == 2 ? std::abs(u.x() * v.y() - u.y() * v.x()) == 0 : u.cross(v).squaredNorm() == 0)
        throw bad("edge vectors must be nonzero and not parallel");
      if (!(std::isfinite(w.radius) && w.radius >= 0))
        throw bad("hole radius \"" + num(w.radius) + "\" must be a non-negative number");
      break;
    }
    case WallKind::box:
      if (!((planar(w.p[1]) - planar(w.p[0])).array() >= 0).all())
        throw bad("minimum corner must not exceed maximum corner");
      break;
    case WallKind::drum:
      if (!(std::isfinite(w.radius) && w.radius > 0))
        throw bad("radius \"" + num(w.radius) + "\" must be a positive number");
      if (dim == 3 && !(std::isfinite(w.length) && w.length > 0))
        throw bad("length \"" + num(w.length) + "\" must be a positive number");
      if (dim == 3 && w.p[1].squaredNorm() == 0) throw bad("axis must be a nonzero vector");
      break;
    case WallKind::triangle:
      if (dim != 3) throw bad("a triangle is a 3D wall");
      break;
    default:
      throw bad("unknown kind");
  }
}

}  // namespace

void checkScene(const RenderScene& s) {
  if (s.dim != 2 && s.dim != 3)
    throw Error("bad dimension \"" + std::to_string(s.dim) + "\": must be 2 or 3",
                {"VALUE", "DIMENSION"});
  const size_t n = s.size();
  checkLength("centres", s.centres.size(), n * s.dim);
  if (!s.colours.empty()) checkLength("colours", s.colours.size(), 3 * n);
  if (!s.field.empty()) checkLength("field", s.field.size(), n);
  if (!s.angles.empty()) checkLength("angles", s.angles.size(), n);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < s.dim; ++k)
      if (!std::isfinite(s.centres[i * s.dim + k]))
        throw Error("bad position for " + indexed("grain", i) + ": coordinate " +
                        std::to_string(k) + " is \"" + num(s.centres[i * s.dim + k]) +
                        "\", must be a finite number",
                    {"VALUE", "POSITION"});
    if (!(std::isfinite(s.radii[i]) && s.radii[i] > 0))
      throw Error("bad radius \"" + num(s.radii[i]) + "\" for " + indexed("grain", i) +
                      ": must be a positive number",
                  {"VALUE", "RADIUS"});
  }
  for (size_t i = 0; i < s.colours.size(); ++i)
    if (!(s.colours[i] >= 0 && s.colours[i] <= 1))
      throw Error("bad colour \"" + num(s.colours[i]) + "\" for " + indexed("grain", i / 3) +
                      ": must be a number from 0 to 1",
                  {"VALUE", "COLOUR"});
  for (size_t i = 0; i < s.field.size(); ++i)
    if (!std::isfinite(s.field[i]))
      throw Error("bad field value \"" + num(s.field[i]) + "\" for " + indexed("grain", i) +
                      ": must be a finite number",
                  {"VALUE", "FIELD"});
  for (size_t i = 0; i < s.angles.size(); ++i)
    if (!std::isfinite(s.angles[i]))
      throw Error("bad angle \"" + num(s.angles[i]) + "\" for " + indexed("grain", i) +
                      ": must be a finite number",
                  {"VALUE", "ANGLE"});
  for (size_t i = 0; i < s.walls.size(); ++i) checkWall(s.walls[i], i, s.dim);
  for (size_t i = 0; i < s.chains.size(); ++i) {
    const ChainLink& l = s.chains[i];
    if (l.a >= n || l.b >= n || !(std::isfinite(l.force) && l.force >= 0))
      throw Error("bad " + indexed("chain", i) +
                      ": its grains must be below the grain count and its force finite, >= 0",
                  {"VALUE", "CHAIN"});
  }
  for (uint32_t i : s.highlighted)
    if (i >= n)
      throw Error("bad highlighted grain \"" + std::to_string(i) +
                      "\": must be below the grain count " + std::to_string(n),
                  {"VALUE", "HIGHLIGHT"});
  if (!s.meshOf.empty()) {
    checkLength("mesh indices", s.meshOf.size(), n);
    if (s.dim == 3) checkLength("orientations", s.orientations.size(), 4 * n);
    for (size_t i = 0; i < n; ++i) {
      if (s.meshOf[i] < -1 || s.meshOf[i] >= static_cast<long>(s.meshes.size()))
        throw Error("bad mesh index \"" + std::to_string(s.meshOf[i]) + "\" for " +
                        indexed("grain", i) + ": must be -1 or below the number of meshes",
                    {"VALUE", "MESH"});
    }
    for (size_t i = 0; i < s.orientations.size(); ++i)
      if (!std::isfinite(s.orientations[i]))
        throw Error("bad orientation for " + indexed("grain", i / 4) + ": must be finite numbers",
                    {"VALUE", "ORIENTATION"});
    for (size_t m = 0; m < s.meshes.size(); ++m) {
      const bool finite = std::all_of(s.meshes[m].begin(), s.meshes[m].end(),
                                      [](const Vec3& p) { return p.allFinite(); });
      if (s.meshes[m].size() % 3 != 0 || !finite)
        throw Error("bad mesh " + std::to_string(m) +
                        ": must be triangles (3 points each) of finite coordinates",
                    {"VALUE", "MESH"});
    }
  }
  if (std::isinf(s.time))
    throw Error("bad time \"" + num(s.time) + "\": must be a finite number or NaN for none",
                {"VALUE", "TIME"});
  if (!s.bounds.empty() && !(s.bounds.lo.allFinite() && s.bounds.hi.allFinite()))
    throw Error("bad bounds: corners must be finite", {"VALUE", "BOUNDS"});
}

void checkOptions(const RenderOptions& o) {
  const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
  if (o.width < 1 || o.height < 1 || o.width > kMaxImageSize || o.height > kMaxImageSize)
    throw Error("bad size \"" + size + "\": must be two positive integers up to " +
                    std::to_string(kMaxImageSize),
                {"VALUE", "SIZE"});
  if (o.antialias < 1 || o.antialias > 4)
    throw Error("bad antialias \"" + std::to_string(o.antialias) + "\": must be 1, 2, 3 or 4",
                {"VALUE", "ANTIALIAS"});
  if (long(o.width) * o.antialias > kMaxImageSize || long(o.height) * o.antialias > kMaxImageSize)
    throw Error("bad size \"" + size + "\": with antialias " + std::to_string(o.antialias) +
                    " each side must be at most " + std::to_string(kMaxImageSize / o.antialias),
                {"VALUE", "SIZE"});
  if (o.stripPixels < 1)
    throw Error("bad strip \"" + std::to_string(o.stripPixels) + "\": must be at least 1 pixel",
                {"VALUE", "STRIP"});
  for (const Rgb* c : {&o.background, &o.defaultColour, &o.outlineColour})
    if (!unitColour(*c))
      throw Error("bad colour: components must be numbers from 0 to 1", {"VALUE", "COLOUR"});
  const CameraDef& c = o.camera;
  if (!(c.fov > 0 && c.fov < 180))
    throw Error(
        "bad field of view \"" + num(c.fov) + "\": must be a number of degrees between 0 and 180",
        {"VALUE", "FOV"});
  if (!(std::isfinite(c.viewHeight) && c.viewHeight >= 0))
    throw Error("bad view height \"" + num(c.viewHeight) + "\": must be a nonnegative number",
                {"VALUE", "CAMERA"});
  if (!finite3(c.position) || !finite3(c.lookAt) || !finite3(c.up) || !finite3(c.direction))
    throw Error("bad camera: coordinates must be finite numbers", {"VALUE", "CAMERA"});
  const Vec3 view = c.automatic ? c.direction : Vec3(c.lookAt - c.position);
  if (view.squaredNorm() == 0)
    throw Error(c.automatic ? "bad camera: direction must be a nonzero vector"
                            : "bad camera: position and look-at point must differ",
                {"VALUE", "CAMERA"});
  if (view.normalized().cross(c.up).norm() < 1e-6 * c.up.norm() || c.up.squaredNorm() == 0)
    throw Error("bad camera: up vector must be nonzero and not parallel to the view direction",
                {"VALUE", "CAMERA"});
  if (std::isinf(o.fieldMin) || std::isinf(o.fieldMax) || o.fieldMin >= o.fieldMax)
    throw Error("bad field range \"" + num(o.fieldMin) + " " + num(o.fieldMax) +
                    "\": must be finite with minimum below maximum",
                {"VALUE", "RANGE"});
  if (!(std::isfinite(o.outlineWidth) && o.outlineWidth >= 0 && o.outlineWidth <= 100))
    throw Error("bad outline width \"" + num(o.outlineWidth) +
                    "\": must be a number of pixels from 0 to 100",
                {"VALUE", "OUTLINE"});
  if (!(std::isfinite(o.wallWidth) && o.wallWidth > 0 && o.wallWidth <= 100))
    throw Error(
        "bad wall width \"" + num(o.wallWidth) + "\": must be a number of pixels above 0 up to 100",
        {"VALUE", "WIDTH"});
  if (o.legendWidth < 0 || o.legendWidth >= o.width)
    throw Error("bad legend width \"" + std::to_string(o.legendWidth) +
                    "\": must be 0 (as wide as its labels need) or pixels below the image width",
                {"VALUE", "WIDTH"});
  if (!(o.wallAlpha >= 0 && o.wallAlpha <= 1))
    throw Error("bad wall opacity \"" + num(o.wallAlpha) + "\": must be a number from 0 to 1",
                {"VALUE", "COLOUR"});
}

}  // namespace demlab::render
