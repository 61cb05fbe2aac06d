#include "cmd/commands/snapshot_options.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <map>

#include "cmd/words.hpp"
#include "core/memory_budget.hpp"
#include "core/tag_table.hpp"

namespace demlab::cmd {
namespace {

// The fields grains can be coloured by, with their SI units ("" for none).
const std::vector<std::pair<std::string, std::string>> kFields = {
    {"speed", "m/s"}, {"spin", "rad/s"},  {"force", "N"},    {"contactforce", "N"},
    {"radius", "m"},  {"id", ""},         {"material", ""},  {"tag", ""},
    {"value", ""}};

// Sorted, as Tcl lists alternatives in its messages.
const std::vector<std::string> kColourMaps = {"categorical", "coolwarm", "inferno",
                                              "magma",       "plasma",   "viridis"};

const std::map<std::string, Colour, std::less<>>& colourNames() {
  static const std::map<std::string, Colour, std::less<>> m = {
      {"black", {0, 0, 0}},
      {"white", {1, 1, 1}},
      {"grey", {0.5f, 0.5f, 0.5f}},
      {"gray", {0.5f, 0.5f, 0.5f}},
      {"red", {0.84f, 0.15f, 0.16f}},
      {"green", {0.17f, 0.63f, 0.17f}},
      {"blue", {0.12f, 0.47f, 0.71f}},
      {"orange", {1.0f, 0.5f, 0.05f}},
      {"yellow", {0.99f, 0.85f, 0.2f}},
      {"purple", {0.58f, 0.4f, 0.74f}},
  };
  return m;
}

// Returns whether word names a field grains can be coloured by.
bool isField(const std::string& word) {
  return std::any_of(kFields.begin(), kFields.end(), [&](auto& f) { return f.first == word; });
}

// Returns the colour `word` names (#rrggbb or a name). Throws {VALUE <PARAM>} otherwise.
Colour parseColour(const Call& c, std::string_view param, const std::string& word) {
  if (word.size() == 7 && word[0] == '#' &&
      word.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
    Colour k;
    for (int i = 0; i < 3; ++i)
      k[std::size_t(i)] =
          float(std::stoi(word.substr(std::size_t(1 + 2 * i), 2), nullptr, 16)) / 255.0f;
    return k;
  }
  if (auto it = colourNames().find(word); it != colourNames().end()) return it->second;
  std::vector<std::string> names;
  for (auto& kv : colourNames()) names.push_back(kv.first);
  c.bad(param, "must be #rrggbb or a colour name: " + alternatives(names));
}

// Returns the numbers of the list in `param`, which must hold exactly n finite reals. Throws
// {VALUE <PARAM>} with why.
std::vector<double> finiteReals(const Call& c, std::string_view param, size_t n,
                                const std::string& why) {
  std::vector<double> out;
  for (const std::string& w : splitList(c.str(param))) {
    double v;
    if (!readReal(w, v) || !std::isfinite(v)) c.bad(param, why);
    out.push_back(v);
  }
  if (out.size() != n) c.bad(param, why);
  return out;
}

// Reads -range into o: {lo hi}, "first" or "auto"; a series defaults to first.
void readRange(const Call& c, bool now, SnapOptions& o) {
  const std::string word = c.has("range") ? c.str("range") : now ? "auto" : "first";
  if (word == "first") {
    o.rangeFirst = true;
  } else if (word != "auto") {
    const std::string why = "must be auto, first, or {min max}: two finite numbers with min < max";
    const auto r = finiteReals(c, "range", 2, why);
    if (!(r[0] < r[1])) c.bad("range", why);
    o.range = std::array<double, 2>{r[0], r[1]};
  }
}

// Reads -clip into o: a point and a normal (made unit length) of the plane.
void readClip(const Call& c, SnapOptions& o) {
  const std::string why = "must be {px py pz nx ny nz}: a point and a nonzero normal";
  const auto v = finiteReals(c, "clip", 6, why);
  const double len = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
  if (!(len > 0)) c.bad("clip", why);
  o.clip = std::array<double, 6>{v[0], v[1], v[2], v[3] / len, v[4] / len, v[5] / len};
}

}  // namespace

bool isJpegName(const Call& c, std::string_view param) {
  const std::string name = std::filesystem::path(c.str(param)).filename().string();
  const size_t dot = name.find_last_of('.');
  std::string ext;
  if (dot != std::string::npos)
    for (char ch : name.substr(dot + 1)) ext += char(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == "jpg" || ext == "jpeg") return true;
  if (ext != "png") c.bad(param, "must end in .jpeg, .jpg, or .png");
  return false;
}

std::string fieldUnit(const std::string& field) {
  for (const auto& [name, unit] : kFields)
    if (name == field) return unit;
  return "";
}

void drawingOptions(Command& c, bool series) {
  c.option("size", text("WxH"), "image size in pixels, e.g. 1280x720").byDefault("800x600");
  c.option("color", text("field or colour"),
           "colour by a field (speed, spin, force: the net force, contactforce: the sum of the "
           "magnitudes of a grain's contact forces, radius, id, material, tag, value) or one "
           "colour (#rrggbb or a name)")
      .byDefault("speed");
  c.option("colormap", choice(kColourMaps),
           "colour map (default: categorical for id, material and tag, else viridis)");
  c.option("range", text("{min max}, first or auto").asList(),
           series ? "field values mapped over the colour map: {min max}, first (fixed at the "
                    "first frame whose values differ; the default, so colours mean the same in "
                    "every frame) or auto (each frame its own)"
                  : "field values mapped over the colour map: {min max} or auto (the default: "
                    "the frame's own)");
  c.option("tags", tagList(),
           "draw only the grains with one of these tags (with -color tag: one colour each)");
  c.option("values", reals(), "with -color value: one number per element, in element order");
  c.option("unit", text("unit"), "with -color value: the values' unit, shown in the legend");
  c.option("position", vector(3).withUnit("m"), "3D camera position (default: automatic)");
  c.option("lookat", vector(3).withUnit("m"), "3D point the camera looks at");
  c.option("up", vector(3), "3D camera up direction").byDefault("0 0 1");
  c.option("fov", real().min(0, true).max(180, true).withUnit("deg"), "vertical field of view")
      .byDefault("30");
  c.flag("ortho", "3D: orthographic projection (2D is always orthographic)");
  c.option("viewheight", real().nonNegative().withUnit("m"),
           "orthographic: world height of the frame (0: fit the scene)")
      .byDefault("0");
  if (series)
    c.option("camera", choice({"fixed", "auto"}),
             "automatic framing: fixed (computed at the first frame and kept, so the film does "
             "not jump) or auto (each frame fits the scene)")
        .byDefault("fixed");
  c.option("background", text("colour"), "background colour (#rrggbb or a name)")
      .byDefault("white");
  c.option("antialias", integer().range(1, 4), "supersampling factor per axis").byDefault("2");
  c.option("legend", boolean(),
           "draw the colour legend (ticks, name and unit) in a strip right of the scene when "
           "colouring by a field")
      .byDefault("1");
  c.option("timestamp", boolean(), "stamp the simulated time above the scene").byDefault("1");
  c.option("title", text("text"), "a title above the scene");
  c.option("quality", integer().range(1, 100), "JPEG quality").byDefault("90");
  c.option("chains", boolean(),
           "draw force chains: a line between the centres of each pair of touching grains, "
           "wider and darker the larger the force, over the grains")
      .byDefault("0");
  c.option("chainmin", real().nonNegative(),
           "with -chains: draw only contacts whose force exceeds this fraction of the mean")
      .byDefault("1");
  c.option("clip", text("{px py pz nx ny nz}").asList(),
           "leave out the grains whose centre lies on the normal's side of this plane (whole "
           "grains: none is cut; in 2D the x and y parts count)");
  c.option("walls", boolean(), "draw the walls").byDefault("1");
  c.option("highlight", text("elements").asList(),
           "elements (ids or names) drawn in magenta over the colouring: a selection");
}

SnapOptions readOptions(const Call& c, bool now) {
  SnapOptions o;
  const std::string& size = c.str("size");
  {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(size.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 ||
        h < 1 || w > 16384 || h > 16384)
      c.bad("size", "must be WIDTHxHEIGHT, each 1 to 16384 pixels");
    o.width = w;
    o.height = h;
  }
  const std::string& by = c.str("color");
  if (isField(by)) {
    o.colourBy = by;
  } else {
    o.fixed = parseColour(c, "color", by);
  }
  if (c.given("tags")) {
    for (auto& t : splitList(c.str("tags"))) {
      checkTagName(t);
      o.tags.push_back(t);
    }
    if (o.tags.empty()) c.bad("tags", "must name at least one tag");
  }
  if (o.colourBy == "tag" && o.tags.empty()) c.bad("tags", "-color tag needs -tags {tag ...}");
  if (c.given("values")) {
    if (o.colourBy != "value") c.bad("values", "needs -color value");
    if (!now) c.bad("values", "a fixed list of values only fits \"snapshot write\"");
    o.values = c.vec("values");
    if (session(c.context()).scene().distributed()) {
      throw Error("snapshots of a distributed scene can't draw -color value yet",
                  {"MPI", "UNSUPPORTED"});
    }
    const std::size_t n = session(c.context()).scene().elementCount();
    if (o.values.size() != n) {
      c.bad("values", "expected " + std::to_string(n) + " numbers (one per element) but got " +
                          std::to_string(o.values.size()));
    }
  }
  if (o.colourBy == "value" && !c.given("values"))
    c.bad("values", "-color value needs -values {v ...}");
  if (c.given("unit")) {
    if (o.colourBy != "value") c.bad("unit", "needs -color value (the other fields have their own)");
    o.valueUnit = c.str("unit");
  }
  if (c.has("colormap")) o.colourMap = c.str("colormap");
  readRange(c, now, o);
  o.cameraFixed = !now && c.str("camera") == "fixed";
  if (c.given("position") || c.given("lookat")) {
    if (!c.given("position") || !c.given("lookat"))
      c.bad(c.given("position") ? "lookat" : "position", "-position and -lookat go together");
    o.camera = true;
    o.position = vec3(c.vec("position"));
    o.lookAt = vec3(c.vec("lookat"));
    if (o.position == o.lookAt) c.bad("lookat", "must differ from -position");
  }
  o.up = vec3(c.vec("up"));
  if (o.up == sim::Vec3d{0, 0, 0}) c.bad("up", "must not be the zero vector");
  // A direction: scaled by its largest component, so {1e-300 0 0} does not underflow to zero.
  const double largest = std::max({std::fabs(o.up[0]), std::fabs(o.up[1]), std::fabs(o.up[2])});
  for (double& x : o.up) x /= largest;
  o.fov = c.real("fov");
  o.ortho = c.flag("ortho");
  o.viewHeight = c.real("viewheight");
  o.background = parseColour(c, "background", c.str("background"));
  o.antialias = int(c.integer("antialias"));
  // The renderer draws antialias^2 times the pixels, 4 bytes of colour and 4 of depth each,
  // and reads the colour back: checked before the buffers are made.
  checkMemoryBudget(double(o.width) * o.height * o.antialias * o.antialias * 12,
                    "a " + size + " image with antialias " + std::to_string(o.antialias));
  o.legend = c.get<bool>("legend");
  o.timeStamp = c.get<bool>("timestamp");
  if (c.given("title")) o.title = c.str("title");
  o.quality = int(c.integer("quality"));
  o.chains = c.get<bool>("chains");
  o.chainMin = c.real("chainmin");
  if (c.given("clip")) readClip(c, o);
  o.walls = c.get<bool>("walls");
  if (c.given("highlight")) {
    Param ref;
    ref.name = "highlight";
    ref.type = elementRef();
    for (const std::string& w : splitList(c.str("highlight")))
      o.highlight.push_back(
          scriptId(std::any_cast<sim::ElementId>(convertWord(w, ref, c.context()))));
  }
  return o;
}

}  // namespace demlab::cmd
