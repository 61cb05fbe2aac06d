// The "snapshot" group: off-screen frames of the scene (src/render, OSMesa) written as PNG, now
// (`snapshot write`) or by an output module every so many steps or seconds (`snapshot every`).
// The options are parsed and checked the same way whether or not the build has the renderer;
// without it (DEMLAB_RENDER off, or OSMesa/libpng missing) the commands that draw fail in their
// check phase with DEMLAB UNSUPPORTED RENDER, so a script learns it before anything changed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/tag_table.hpp"

#ifdef DEMLAB_HAVE_RENDER
#include "render/colour_map.hpp"
#include "render/png.hpp"
#include "render/renderer.hpp"
#endif

namespace demlab::cmd {

namespace {

using Colour = std::array<float, 3>;

// What the drawing options ask for, independent of the renderer's types (so the no-renderer
// build parses and checks exactly the same calls).
struct SnapOptions {
  int width = 800, height = 600;
  std::string colourBy;           // a field name, or "" with fixed set
  std::optional<Colour> fixed;    // -color #rrggbb or a colour name
  std::string colourMap;          // "" : by field (categorical for id, material, tag)
  std::vector<std::string> tags;  // -color tag: the categories, in order
  std::vector<double> values;     // -color value: one per element
  std::optional<std::array<double, 2>> range;
  bool camera = false;  // any of position, lookat, up given
  sim::Vec3d position{0, -10, 0}, lookAt{}, up{0, 0, 1};
  double fov = 30, viewHeight = 0;
  bool ortho = false;
  Colour background{1, 1, 1};
  int antialias = 2;
  bool legend = true, timeStamp = true;
};

const std::vector<std::string> kFields = {"speed", "spin",     "force", "radius",
                                          "id",    "material", "tag",   "value"};

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

// Declares the drawing options every drawing subcommand takes.
void drawingOptions(Command& c) {
  c.option("size", text("WxH"), "image size in pixels, e.g. 1280x720").byDefault("800x600");
  c.option("color", text("field or colour"),
           "colour by a field (speed, spin, force, radius, id, material, tag, value) or one "
           "colour (#rrggbb or a name)")
      .byDefault("speed");
  c.option("colormap", choice({"viridis", "categorical"}),
           "colour map (default: categorical for id, material and tag, else viridis)");
  c.option("range", reals(), "{min max} of the field mapped over the colour map");
  c.option("tags", text("list of tags"), "with -color tag: the tags, one colour each");
  c.option("values", reals(), "with -color value: one number per element, in element order");
  c.option("position", vector(3).withUnit("m"), "3D camera position (default: automatic)");
  c.option("lookat", vector(3).withUnit("m"), "3D point the camera looks at");
  c.option("up", vector(3), "3D camera up direction").byDefault("0 0 1");
  c.option("fov", real().min(0, true).max(180, true).withUnit("deg"), "vertical field of view")
      .byDefault("30");
  c.flag("ortho", "3D: orthographic projection (2D is always orthographic)");
  c.option("viewheight", real().nonNegative().withUnit("m"),
           "orthographic: world height of the frame (0: fit the scene)")
      .byDefault("0");
  c.option("background", text("colour"), "background colour (#rrggbb or a name)")
      .byDefault("white");
  c.option("antialias", integer().range(1, 4), "supersampling factor per axis").byDefault("2");
  c.option("legend", boolean(), "draw the colour legend when colouring by a field").byDefault("1");
  c.option("timestamp", boolean(), "stamp the simulated time on the frame").byDefault("1");
}

// Check phase: returns the options of the call, every one checked. Throws {VALUE <PARAM>}.
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
  if (std::find(kFields.begin(), kFields.end(), by) != kFields.end()) {
    o.colourBy = by;
  } else {
    o.fixed = parseColour(c, "color", by);
  }
  if (c.given("tags")) {
    if (o.colourBy != "tag") c.bad("tags", "needs -color tag");
    for (auto& t : splitList(c.str("tags"))) {
      checkTagName(t);
      o.tags.push_back(t);
    }
  }
  if (o.colourBy == "tag" && o.tags.empty()) c.bad("tags", "-color tag needs -tags {tag ...}");
  if (c.given("values")) {
    if (o.colourBy != "value") c.bad("values", "needs -color value");
    if (!now) c.bad("values", "a fixed list of values only fits \"snapshot write\"");
    o.values = c.vec("values");
    const std::size_t n = session(c.context()).scene().elementCount();
    if (o.values.size() != n) {
      c.bad("values", "expected " + std::to_string(n) + " numbers (one per element) but got " +
                          std::to_string(o.values.size()));
    }
  }
  if (o.colourBy == "value" && !c.given("values"))
    c.bad("values", "-color value needs -values {v ...}");
  if (c.has("colormap")) o.colourMap = c.str("colormap");
  if (c.given("range")) {
    const auto& r = c.vec("range");
    if (r.size() != 2 || !(r[0] < r[1]) || !std::isfinite(r[0]) || !std::isfinite(r[1]))
      c.bad("range", "must be two finite numbers {min max} with min < max");
    o.range = std::array<double, 2>{r[0], r[1]};
  }
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
  o.fov = c.real("fov");
  o.ortho = c.flag("ortho");
  o.viewHeight = c.real("viewheight");
  o.background = parseColour(c, "background", c.str("background"));
  o.antialias = int(c.integer("antialias"));
  o.legend = c.get<bool>("legend");
  o.timeStamp = c.get<bool>("timestamp");
  return o;
}

[[noreturn, maybe_unused]] void unsupported() {
  throw Error(
      "snapshots are not available: demlab was built without the renderer (configure with "
      "-DDEMLAB_RENDER=ON and install libosmesa6-dev and libpng-dev)",
      {"UNSUPPORTED", "RENDER"});
}

#ifdef DEMLAB_HAVE_RENDER

using render::RenderWall;

// The process's one renderer (an OSMesa context), made on first use and kept: a context costs
// tens of milliseconds, a frame of a small scene less.
render::Renderer& theRenderer() {
  static std::unique_ptr<render::Renderer> r;
  if (!r) r = render::makeRenderer();
  return *r;
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
        if (d == 2) {
          out.push_back(RenderWall::segment(c - h[0] * a0, c + h[0] * a0));
        } else {
          out.push_back(
              RenderWall::rectangle(c - h[0] * a0 - h[1] * a1, 2 * h[0] * a0, 2 * h[1] * a1));
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
    }
  }
  return out;
}

// The arrays a RenderScene views; they must outlive the render call.
struct FrameData {
  std::vector<double> centres, radii, field, angles, orientations;
  std::vector<float> colours;
  std::vector<int32_t> meshOf;
  render::RenderScene scene;
};

// Returns the frame of s as o asks (the scene part). Reads the scene only.
void buildFrame(const sim::Simulation& s, const SnapOptions& o, FrameData& f) {
  const int d = s.dim();
  f.centres = s.positions();
  f.radii = s.radii();
  const std::size_t n = f.radii.size();
  render::RenderScene& sc = f.scene;
  sc.dim = d;
  sc.categoryNames.clear();
  if (d == 2) f.angles = s.orientations();
  const std::string& by = o.colourBy;
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
  } else if (by == "spin") {
    norms(s.angularVelocities(), d == 2 ? 1 : 3);
  } else if (by == "radius") {
    f.field = f.radii;
  } else if (by == "value") {
    f.field = o.values;
  } else if (by == "id") {
    f.field.clear();
    for (sim::ElementId id : s.elementIds()) f.field.push_back(double(scriptId(id)));
  } else if (by == "material") {
    const auto names = s.materialNames();
    f.field.clear();
    for (sim::ElementId id : s.elementIds()) {
      const std::string m = s.element(id).material;
      f.field.push_back(double(std::find(names.begin(), names.end(), m) - names.begin()));
    }
    sc.categoryNames = names;
  } else {  // tag: the first of o.tags a grain carries; "other" for none
    std::unordered_map<std::uint64_t, std::size_t> dense;
    const auto ids = s.elementIds();
    for (std::size_t i = 0; i < ids.size(); ++i) dense[ids[i].bits()] = i;
    f.field.assign(n, double(o.tags.size()));
    for (std::size_t k = o.tags.size(); k-- > 0;)
      for (sim::ElementId id : s.elementsTagged(o.tags[k])) f.field[dense[id.bits()]] = double(k);
    sc.categoryNames = o.tags;
    if (std::any_of(f.field.begin(), f.field.end(),
                    [&](double v) { return v == double(o.tags.size()); }))
      sc.categoryNames.push_back("other");
  }
  sc.centres = f.centres;
  sc.radii = f.radii;
  sc.colours = o.fixed ? std::span<const float>(f.colours) : std::span<const float>();
  sc.field = o.fixed ? std::span<const double>() : std::span<const double>(f.field);
  sc.fieldName = o.fixed ? "" : by == "tag" ? "tag" : by;
  sc.angles = d == 2 ? std::span<const double>(f.angles) : std::span<const double>();
  sc.walls = renderWalls(s);
  // Elements of shapes with a render row are drawn as their meshes.
  sim::Simulation::ElementMeshes m = s.elementMeshes();
  f.meshOf = std::move(m.meshOf);
  sc.meshes.clear();
  for (const auto& mesh : m.meshes) {
    sc.meshes.emplace_back();
    for (const sim::Vec3d& p : mesh) sc.meshes.back().push_back(Vec3(p[0], p[1], p[2]));
  }
  if (!f.meshOf.empty() && d == 3) f.orientations = s.orientations();
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

// Returns nothing; renders s as o asks into path (atomically). Throws the renderer's errors
// (RENDER CONTEXT, VALUE ..., IO PNG); changes only the file.
void writeFrame(const sim::Simulation& s, const SnapOptions& o, const std::string& path) {
  FrameData f;
  buildFrame(s, o, f);
  render::renderPng(theRenderer(), f.scene, renderOptions(o), path);
}

#endif  // DEMLAB_HAVE_RENDER

// One `snapshot every`: where its frames go and how many it wrote. Owned by the output's
// callback; the table below only watches it, for `snapshot list`.
struct Job {
  std::string dir;
  SnapOptions options;
  std::uint64_t frames = 0;
};

std::map<std::pair<const void*, std::uint64_t>, std::weak_ptr<Job>>& jobs() {
  static std::map<std::pair<const void*, std::uint64_t>, std::weak_ptr<Job>> j;
  std::erase_if(j, [](const auto& kv) { return kv.second.expired(); });
  return j;
}

std::string framePath(const Job& j, std::uint64_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(k));
  return (std::filesystem::path(j.dir) / name).string();
}

// Returns the snapshot outputs of s with their jobs, in firing order.
std::vector<std::pair<sim::OutputInfo, std::shared_ptr<Job>>> snapshotOutputs(
    const sim::Simulation& s) {
  std::vector<std::pair<sim::OutputInfo, std::shared_ptr<Job>>> out;
  auto& j = jobs();
  for (const sim::OutputInfo& o : s.outputs()) {
    auto it = j.find({&s, o.id.bits()});
    if (it == j.end()) continue;
    if (auto p = it->second.lock()) out.emplace_back(o, p);
  }
  return out;
}

// A snapshot output id, as `snapshot every` returned it; value: sim::OutputId.
PipeType snapshotRef() {
  return custom("snapshot id", [](std::string_view w, const Param& p, const Context& ctx) {
    std::int64_t id;
    if (readInt(w, id)) {
      const auto h = fromScriptId<sim::OutputId>(id);
      for (auto& [info, job] : snapshotOutputs(session(ctx).scene()))
        if (info.id == h) return std::any(h);
    }
    throw Error(
        "no snapshot output \"" + std::string(w) + "\" (" + p.name + "): see \"snapshot list\"",
        {"LOOKUP", "SNAPSHOT"});
  });
}

}  // namespace

void registerSnapshotCommands(Registry& r) {
  r.describe("snapshot", "Off-screen frames of the scene written as PNG, now or during runs.");

  Command& write =
      r.add("snapshot write", "Renders the scene now into a PNG file; returns its path.");
  write.details =
      "2D scenes are seen from above, discs with a mark showing their rotation; 3D scenes from "
      "an automatic viewpoint unless -position and -lookat are given. The file is replaced "
      "atomically.";
  write.arg("file", text("file"), "the PNG file to write");
  drawingOptions(write);
  write.changesScene = false;
  write.onCheck([](Call& c) {
    c.prepared = readOptions(c, true);
#ifndef DEMLAB_HAVE_RENDER
    unsupported();
#endif
  });
  write.run([](Call& c) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    writeFrame(session(c).scene(), std::any_cast<const SnapOptions&>(c.prepared), c.str("file"));
    return Value(c.str("file"));
#else
    (void)c;
    unsupported();
#endif
  });

  // The spelling, `snapshot frame.png`, for the commonest use.
  r.shorthand("snapshot", "write", ".png");

  Command& every = r.add("snapshot every",
                         "Adds a snapshot output: a frame every N steps or T seconds; returns "
                         "its id.");
  every.details =
      "Frames go to DIR/frame_000000.png, frame_000001.png, ...; frame 0 is the scene as it is "
      "now, written at once (DIR is created if needed). The output runs at the end of each "
      "step it is due at, in every run, until \"snapshot off\". A scene with no snapshot "
      "output runs no rendering code.";
  every.option("steps", integer().min(1), "a frame every this many steps");
  every.option("time", real().positive().withUnit("s"), "a frame every this much simulated time");
  every.oneOf({"steps", "time"}, true);
  every.option("dir", text("folder"), "the folder of the frames").byDefault("frames");
  every.option("first", integer().min(0), "number of the first frame").byDefault("0");
  drawingOptions(every);
  every.onCheck([](Call& c) {
    c.prepared = readOptions(c, false);
#ifndef DEMLAB_HAVE_RENDER
    unsupported();
#endif
  });
  every.run([](Call& c) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    sim::Simulation& s = session(c).scene();
    auto job = std::make_shared<Job>();
    job->dir = c.str("dir");
    job->options = std::any_cast<const SnapOptions&>(c.prepared);
    job->frames = std::uint64_t(c.integer("first"));
    namespace fs = std::filesystem;
    std::error_code ec;
    const bool made = !fs::exists(job->dir, ec) && fs::create_directories(job->dir, ec);
    if (ec) throw Error("can't create folder \"" + job->dir + "\": " + ec.message(), {"IO", "DIR"});
    try {
      writeFrame(s, job->options, framePath(*job, job->frames));
    } catch (...) {
      if (made) fs::remove(job->dir, ec);
      throw;
    }
    ++job->frames;
    sim::OutputDef d;
    d.name = "snapshot " + job->dir;
    if (c.given("steps")) d.everySteps = std::uint64_t(c.integer("steps"));
    if (c.given("time")) d.everyTime = c.real("time");
    d.callback = [job](const sim::Simulation& sim) {
      writeFrame(sim, job->options, framePath(*job, job->frames));
      ++job->frames;
    };
    const sim::OutputId id = s.addOutput(d);
    jobs()[{&s, id.bits()}] = job;
    return Value(scriptId(id));
#else
    (void)c;
    unsupported();
#endif
  });

  Command& list = r.add("snapshot list", "Returns the snapshot outputs as a list of dicts.");
  list.details = "Each dict: id, dir, steps or time (the interval), frames (written so far).";
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (auto& [info, job] : snapshotOutputs(session(c).scene())) {
      Dict d{{"id", scriptId(info.id)}, {"dir", job->dir}};
      if (info.everySteps)
        d.emplace_back("steps", info.everySteps);
      else
        d.emplace_back("time", info.everyTime);
      d.emplace_back("frames", job->frames);
      l.emplace_back(d);
    }
    return Value(l);
  });

  Command& off =
      r.add("snapshot off", "Removes snapshot outputs (all, or those given); returns how many.");
  off.variadicArg("id", snapshotRef(), "snapshot output ids").optional = true;
  off.run([](Call& c) {
    sim::Simulation& s = session(c).scene();
    std::vector<sim::OutputId> ids;
    if (c.has("id")) {
      for (auto id : c.all<sim::OutputId>("id"))
        if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
    } else {
      for (auto& [info, job] : snapshotOutputs(s)) ids.push_back(info.id);
    }
    for (sim::OutputId id : ids) s.removeOutput(id);
    return Value(ids.size());
  });

  Command& read =
      r.add("snapshot read", "Returns a PNG file's size, and a pixel's colour, as a dict.");
  read.details =
      "For tests and scripts that check a frame: width, height, and with -pixel {x y} (from the "
      "top left) the pixel's {r g b} in 0..255.";
  read.arg("file", text("file"), "a PNG file");
  read.option("pixel", ints(), "{x y} of a pixel");
  read.needsScene = false;
  read.changesScene = false;
  read.run([](Call& c) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    const render::Image img = render::readPng(c.str("file"));
    Dict d{{"width", img.width}, {"height", img.height}};
    if (c.given("pixel")) {
      const auto& p = c.get<std::vector<std::int64_t>>("pixel");
      if (p.size() != 2 || p[0] < 0 || p[1] < 0 || p[0] >= img.width || p[1] >= img.height)
        c.bad("pixel", "must be {x y} inside the " + std::to_string(img.width) + "x" +
                           std::to_string(img.height) + " image");
      const auto px = img.pixel(int(p[0]), int(p[1]));
      d.emplace_back("pixel", List{int(px[0]), int(px[1]), int(px[2])});
    }
    return Value(d);
#else
    (void)c;
    unsupported();
#endif
  });
}

}  // namespace demlab::cmd
