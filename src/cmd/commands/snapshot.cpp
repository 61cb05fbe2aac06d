// The "snapshot" group: off-screen frames of the scene (src/render, OSMesa) written as PNG or
// JPEG, now (`snapshot write`) or by an output module every so many steps or seconds
// (`snapshot every`). The drawing options are in snapshot_options, the frame in snapshot_frame.
// The options are parsed and checked the same way whether or not the build has the renderer;
// without it (DEMLAB_RENDER off, or a library it needs missing) the commands that draw fail in
// their check phase with DEMLAB UNSUPPORTED RENDER, so a script learns it before anything
// changed.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "cmd/commands/commands.hpp"
#include "cmd/commands/output_jobs.hpp"
#include "cmd/commands/snapshot_frame.hpp"
#include "cmd/commands/snapshot_options.hpp"
#include "cmd/words.hpp"

#ifdef DEMLAB_HAVE_RENDER
#include "render/image_file.hpp"
#endif

namespace demlab::cmd {

namespace {

[[noreturn, maybe_unused]] void unsupported() {
  throw Error(
      "snapshots are not available: demlab was built without the renderer (configure with "
      "-DDEMLAB_RENDER=ON and install libosmesa6-dev, libpng-dev, libjpeg-dev and "
      "libfreetype-dev)",
      {"UNSUPPORTED", "RENDER"});
}

// One `snapshot every`: where its frames go, how many it wrote and what it keeps from its
// first frame. Owned by the output's
// callback; the table below only watches it, for `snapshot list`.
struct Job {
  std::string dir;
  SnapOptions options;
  std::uint64_t frames = 0;
  SeriesLock lock;
};

OutputJobs<Job>& jobs() {
  static OutputJobs<Job> j("snapshot");
  return j;
}

std::string framePath(const Job& j, std::uint64_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.%s", static_cast<unsigned long long>(k),
                j.options.jpeg ? "jpg" : "png");
  return (std::filesystem::path(j.dir) / name).string();
}

}  // namespace

void registerSnapshotCommands(Registry& r) {
  r.describe("snapshot", "Off-screen frames of the scene written as PNG or JPEG, now or during runs.");

  Command& write =
      r.add("snapshot write", "Renders the scene now into a PNG or JPEG file; returns its path.");
  write.interruptible = true;
  write.details =
      "2D scenes are seen from above, discs with a mark showing their rotation; 3D scenes from "
      "an automatic viewpoint unless -position and -lookat are given. The file's extension picks "
      "the format: .png, or .jpg/.jpeg (with -quality); any other is refused before anything "
      "is drawn. The colour range is the frame's own unless -range is given. The file is "
      "replaced atomically. In a distributed run rank 0 draws every rank's elements (force "
      "chains, contact forces and -color value are refused there yet).";
  write.onRanks = OnRanks::Collective;
  write.arg("file", text("file"), "the PNG or JPEG file to write");
  drawingOptions(write, false);
  write.changesScene = false;
  write.onCheck([](Call& c) {
    SnapOptions o = readOptions(c, true);
    o.jpeg = isJpegName(c, "file");
    c.prepared = o;
#ifndef DEMLAB_HAVE_RENDER
    unsupported();
#endif
  });
  write.run([](Call& c) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    writeFrame(session(c).scene(), std::any_cast<const SnapOptions&>(c.prepared), c.str("file"),
               nullptr);
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
      "Frames go to DIR/frame_000000.png, frame_000001.png, ... (.jpg with -format jpeg); frame "
      "0 is the scene as it is now, written at once (DIR is created if needed). So that a film "
      "does not flicker or jump, a series by default keeps the colour range of its first frame "
      "whose values differ (-range first) and the automatic framing of its first frame "
      "(-camera fixed). The output runs at the end of each "
      "step it is due at, in every run, until \"snapshot off\". A scene with no snapshot "
      "output runs no rendering code. In a distributed run rank 0 draws the frames.";
  every.option("steps", integer().min(1), "a frame every this many steps");
  every.option("time", real().positive().withUnit("s"), "a frame every this much simulated time");
  every.oneOf({"steps", "time"}, true);
  every.option("dir", text("folder"), "the folder of the frames").byDefault("frames");
  every.option("first", integer().min(0), "number of the first frame").byDefault("0");
  every.option("format", choice({"png", "jpeg"}), "the frames' file format").byDefault("png");
  drawingOptions(every, true);
  every.onCheck([](Call& c) {
    SnapOptions o = readOptions(c, false);
    o.jpeg = c.str("format") == "jpeg";
    c.prepared = o;
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
    OutputJobs<Job>::startIn(job->dir, [&] {
      writeFrame(s, job->options, framePath(*job, job->frames), &job->lock);
    });
    ++job->frames;
    sim::OutputDef d;
    d.name = "snapshot " + job->dir;
    if (c.given("steps")) d.everySteps = std::uint64_t(c.integer("steps"));
    if (c.given("time")) d.everyTime = c.real("time");
    // Frames read the contacts only to colour by contact force or to draw chains.
    d.needsContacts = job->options.chains || job->options.colourBy == "contactforce";
    // Frames of a distributed run: rank 0 draws every rank's elements (not chains, contact
    // forces or per-element values yet: distribute() refuses those).
    d.distributable = !d.needsContacts && job->options.colourBy != "value";
    d.callback = [job](const sim::Simulation& sim) {
      writeFrame(sim, job->options, framePath(*job, job->frames), &job->lock);
      ++job->frames;
    };
    const sim::OutputId id = s.addOutput(d);
    jobs().add(s, id, job);
    return Value(scriptId(id));
#else
    (void)c;
    unsupported();
#endif
  });

  Command& list = r.add("snapshot list", "Returns the snapshot outputs as a list of dicts.");
  list.onRanks = OnRanks::Alike;
  list.details =
      "Each dict: id, dir, steps or time (the interval), frames (written so far), and range "
      "{min max} once the series' colour range is fixed.";
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (auto& [info, job] : jobs().of(session(c).scene())) {
      Dict d{{"id", scriptId(info.id)}, {"dir", job->dir}};
      if (info.everySteps)
        d.emplace_back("steps", info.everySteps);
      else
        d.emplace_back("time", info.everyTime);
      d.emplace_back("frames", job->frames);
      if (job->lock.range) d.emplace_back("range", List{(*job->lock.range)[0], (*job->lock.range)[1]});
      l.emplace_back(d);
    }
    return Value(std::move(l));
  });

  jobs().declareOff(r);

  Command& read =
      r.add("snapshot read", "Returns a PNG or JPEG file's size, and a pixel's colour, as a dict.");
  read.details =
      "For tests and scripts that check a frame: width, height, and with -pixel {x y} (from the "
      "top left) the pixel's {r g b} in 0..255.";
  read.arg("file", text("file"), "a PNG or JPEG file");
  read.option("pixel", ints(), "{x y} of a pixel");
  read.needsScene = false;
  read.changesScene = false;
  read.run([](Call& c) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    const render::Image img = render::readImage(c.str("file"));
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
