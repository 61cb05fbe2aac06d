// What the renderer draws (RenderScene) and how (RenderOptions), in plain arrays and plain
// structs, so the simulation, a test or a file reader can fill them without knowing GL.
//
// RenderScene holds views (std::span) of the caller's arrays: no copy of the hot per-grain data
// is made, and the arrays must outlive the render call. Coordinates are in world units; in 2D
// every point's z (third component of Vec3) is ignored and the centres array has 2 numbers per
// grain. Both structs are checked (checkScene, checkOptions) before any GL work, so a bad call
// throws demlab::Error and draws nothing.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace demlab::render {

using Rgb = std::array<float, 3>;

enum class WallKind { plane, segment, rectangle, box, drum, triangle };

// One wall as a simple geometric description. Meaning of p[0..2] by kind:
//   plane:     p[0] a point on it, p[1] its normal. Drawn clipped to the scene bounds
//              (in 2D: the line through p[0] perpendicular to p[1]).
//   segment:   p[0], p[1] its ends (a line in 3D too).
//   rectangle: p[0] a corner, p[1] and p[2] its two edge vectors (2D: a parallelogram outline);
//              3D: radius > 0 is a circular hole of that radius at its centre (an orifice).
//   box:       p[0] its minimum corner, p[1] its maximum corner (axis-aligned; edges only).
//   drum:      p[0] the centre of its axis, p[1] the axis direction (3D only), radius; length
//              is the cylinder's length along the axis (3D only). In 2D a circle.
struct RenderWall {
  WallKind kind = WallKind::plane;
  std::array<Vec3, 3> p = {Vec3::Zero(), Vec3::UnitZ(), Vec3::Zero()};
  double radius = 0;
  double length = 0;
  Rgb colour = {0.45f, 0.45f, 0.5f};

  // Each returns a wall of its kind with the default colour.
  static RenderWall plane(const Vec3& point, const Vec3& normal);
  static RenderWall segment(const Vec3& a, const Vec3& b);
  static RenderWall rectangle(const Vec3& corner, const Vec3& u, const Vec3& v);
  static RenderWall box(const Vec3& lo, const Vec3& hi);
  static RenderWall drum(const Vec3& centre, const Vec3& axis, double radius, double length);
  // One triangle of a mesh wall (3D), its corners a, b, c.
  static RenderWall triangle(const Vec3& a, const Vec3& b, const Vec3& c);
};

// Axis-aligned bounds; empty when lo > hi on some axis.
struct Bounds {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  bool empty() const { return !(lo.array() <= hi.array()).all(); }
  void add(const Vec3& q, double r = 0) {
    lo = lo.cwiseMin(q - Vec3::Constant(r));
    hi = hi.cwiseMax(q + Vec3::Constant(r));
  }
};

// A force chain: a line between the centres of grains a and b (indices into the scene's grains)
// carrying a contact force of this magnitude (N), drawn wider and darker the larger it is.
struct ChainLink {
  std::uint32_t a = 0, b = 0;
  double force = 0;
};

struct RenderScene {
  int dim = 3;                      // 2 (discs seen from above) or 3 (spheres)
  std::span<const double> centres;  // dim numbers per grain
  std::span<const double> radii;    // one per grain; the grain count n is radii.size()
  // Colour, first that applies: field (through options.colourMap), colours (3 per grain, RGB in
  // [0,1]), else options.defaultColour.
  std::span<const float> colours;
  std::span<const double> field;
  std::string fieldName;                   // the legend's title, e.g. "speed"
  std::string fieldUnit;                   // its SI unit, e.g. "m/s"; "" for none
  std::vector<std::string> categoryNames;  // categorical legend labels by integer value
  std::span<const double> angles;          // 2D: orientation angles (rad) for the rotation mark
  // Grains drawn as triangle meshes instead of spheres or discs (the shape table's render rows,
  // sim/shape.hpp): grain i with meshOf[i] >= 0 is meshes[meshOf[i]], triangles in its body
  // frame (3 points each; 2D: z = 0), turned by orientations (3D: 4 per grain, w x y z) or, in
  // 2D, angles, and placed at its centre. Empty meshOf: every grain a ball.
  std::span<const int32_t> meshOf;
  std::span<const double> orientations;
  std::vector<std::vector<Vec3>> meshes;
  std::vector<RenderWall> walls;
  std::vector<ChainLink> chains;  // drawn over the grains
  std::vector<uint32_t> highlighted;  // grains drawn in options.highlightColour (a selection)
  std::string title;              // drawn above the scene; "" for none
  double time = std::numeric_limits<double>::quiet_NaN();  // NaN: no time stamp
  Bounds bounds;  // empty: computed from the grains and the finite walls

  // Returns the number of grains.
  size_t size() const { return radii.size(); }
};

enum class ColourMap { viridis, magma, inferno, plasma, coolwarm, categorical };

struct CameraDef {
  bool automatic = true;  // frame the whole scene; position and lookAt are then ignored
  Vec3 position = Vec3(0, -10, 0);
  Vec3 lookAt = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  Vec3 direction = Vec3(-0.55, 1.0, -0.55);  // automatic 3D framing looks along this
  double fov = 30;                           // vertical field of view, degrees (perspective)
  bool orthographic = false;                 // 2D scenes are always orthographic from above
  double viewHeight = 0;  // orthographic: world height of the frame; 0 = fit the scene
};

struct RenderOptions {
  int width = 800;
  int height = 600;
  Rgb background = {1, 1, 1};
  Rgb defaultColour = {0.8f, 0.5f, 0.2f};
  Rgb highlightColour = {1.0f, 0.0f, 1.0f};  // magenta: in none of the colour maps
  CameraDef camera;
  ColourMap colourMap = ColourMap::viridis;
  double fieldMin = std::numeric_limits<double>::quiet_NaN();  // NaN: the field's minimum
  double fieldMax = std::numeric_limits<double>::quiet_NaN();  // NaN: the field's maximum
  bool legend = true;                                          // drawn when colouring by a field
  int legendWidth = 0;  // pixels of the legend strip; 0: as wide as its labels need
  bool timeStamp = true;                                       // drawn when scene.time is finite
  int antialias = 2;          // supersampling factor per axis, 1 to 4
  double outlineWidth = 1.0;  // grain outline, pixels of the final image; 0: none
  Rgb outlineColour = {0.1f, 0.1f, 0.1f};
  double wallWidth = 1.5;   // wall lines, pixels of the final image
  double wallAlpha = 0.15;  // opacity of 3D wall surfaces (planes, rectangles, drums)
  bool cullHidden = true;   // 3D: skip grains certainly hidden (occlusion.hpp); same image
  // The frame is drawn in strips of rows of at most this many pixels (at antialias x the size),
  // one framebuffer's worth each, with Ctrl-C polled between them; the image is the same for
  // any value (the tests compare strips against one piece).
  long stripPixels = 1L << 21;
};

inline constexpr int kMaxImageSize = 16384;

// Returns nothing; throws demlab::Error (DEMLAB VALUE ...) naming the first bad field of the
// scene: DIMENSION, LENGTH, POSITION, RADIUS, COLOUR, FIELD, ANGLE, WALL, TIME.
void checkScene(const RenderScene& scene);

// Returns nothing; throws demlab::Error (DEMLAB VALUE ...) naming the first bad option: SIZE,
// ANTIALIAS, COLOUR, CAMERA, FOV, RANGE, OUTLINE, WIDTH (wall or legend).
void checkOptions(const RenderOptions& options);

}  // namespace demlab::render
