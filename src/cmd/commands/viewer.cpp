// The "viewer" group: the scene in a Tk window (tcl/viewer.tcl), drawn by the snapshots'
// renderer into a Tk photo image. The C++ side gives the window what only it can: the frame as
// image bytes (`viewer frame`), the element a pixel shows (`viewer pick`) and the camera a frame
// is seen with (`viewer camera`), each with the drawing options of `snapshot write`, so what is
// picked is what was drawn. The window itself, its camera and buttons are Tcl over Tk, loaded
// only by `viewer open`: a scene without a viewer runs no viewer code. These commands only read
// the scene, so the window may redraw from inside a run (the binding lets the viewer group
// through while a run steps), at most -fps times a second of wall-clock time.
#include <algorithm>
#include <chrono>
#include <functional>
#include <string>

#include "cmd/commands/commands.hpp"
#include "cmd/commands/snapshot_frame.hpp"
#include "cmd/commands/snapshot_options.hpp"
#include "cmd/words.hpp"

extern const char* const demlabViewerTcl;

namespace demlab::cmd {

namespace {

[[noreturn, maybe_unused]] void unsupported() {
  throw Error("the viewer is not available: demlab was built without the renderer",
              {"UNSUPPORTED", "RENDER"});
}

// Returns nothing; evaluates script in the session's interpreter. Throws the script's error as
// a demlab::Error, with its own -errorcode when that starts with DEMLAB, else {code...}.
void evalOrThrow(Session& s, const std::string& script, std::vector<std::string> code) {
  if (!s.evalScript) throw Error("the viewer needs a Tcl interpreter", {"UNSUPPORTED", "TK"});
  Session::ScriptResult r = s.evalScript(script);
  if (r.ok) return;
  if (!r.errorCode.empty() && r.errorCode[0] == "DEMLAB")
    throw Error(r.result, std::vector<std::string>(r.errorCode.begin() + 1, r.errorCode.end()));
  throw Error(r.result, std::move(code));
}

// Returns the result of script, "" when it fails.
std::string evalText(Session& s, const std::string& script) {
  if (!s.evalScript) return "";
  Session::ScriptResult r = s.evalScript(script);
  return r.ok ? r.result : "";
}

// Returns whether the viewer's Tcl (tcl/viewer.tcl) is in the interpreter.
bool viewerLoaded(Session& s) {
  return evalText(s, "namespace exists ::demlab::viewer") == "1";
}

// Returns nothing; evaluates the viewer's Tcl unless it is there already. Throws its error.
void loadViewer(Session& s) {
  if (!viewerLoaded(s)) evalOrThrow(s, demlabViewerTcl, {"INTERNAL", "VIEWER"});
}

// Returns nothing; gives c the drawing options of `snapshot write`, read and checked in its
// check phase (where a build without the renderer fails), and an execute phase that passes the
// checked options to draw. The command only reads the scene. Changes c.
void drawingQuery(Command& c, std::function<Value(Call&, const SnapOptions&)> draw) {
  drawingOptions(c, false);
  c.changesScene = false;
  c.onCheck([](Call& call) {
    call.prepared = readOptions(call, true);
#ifndef DEMLAB_HAVE_RENDER
    unsupported();
#endif
  });
  c.run([draw](Call& call) -> Value {
    return draw(call, std::any_cast<const SnapOptions&>(call.prepared));
  });
}

}  // namespace

void registerViewerCommands(Registry& r) {
  r.describe("viewer",
             "The scene in a Tk window: orbit, pan and zoom, colour menus, play, pause and step, "
             "click an element to see and select it.");

  Command& open = r.add("viewer open", "Opens the viewer window (Tk) on the scene.");
  open.details =
      "Mouse: in 3D, drag with button 1 to orbit about the point looked at, with button 2 or "
      "Shift-button 1 to pan, the wheel to zoom; in 2D, drag to pan and the wheel to zoom. A "
      "click selects the element under the pointer (Control-click adds to the selection) and "
      "shows its state. Play runs the scene in chunks from Tk's event loop; during any run the "
      "window is redrawn at most -fps times a second (wall-clock), and never for more than a "
      "twentieth of the run's time. Needs an X display: without "
      "one it fails with DEMLAB UNSUPPORTED DISPLAY and nothing else is affected. From the "
      "console the window stays live while the prompt waits; in a script, `vwait` keeps it.";
  open.option("size", text("WxH"), "the picture's size in pixels").byDefault("640x480");
  open.option("fps", real().min(0.1).max(60), "redraws per second during runs")
      .byDefault("5");
  open.option("color", choice({"speed", "force", "contactforce", "spin", "radius", "id",
                               "material"}),
              "what the colours show at first").byDefault("speed");
  open.option("legend", boolean(), "draw the colour legend right of the scene").byDefault("1");
  open.option("timestamp", boolean(), "stamp the simulated time above the scene").byDefault("1");
  open.needsScene = false;
  open.changesScene = false;
  open.onCheck([](Call& c) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(c.str("size").c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' ||
        w < 64 || h < 64 || w > 4096 || h > 4096)
      c.bad("size", "must be WIDTHxHEIGHT, each 64 to 4096 pixels");
#ifndef DEMLAB_HAVE_RENDER
    unsupported();
#endif
    Session& s = session(c);
    // Tk first: without a display this is where the viewer stops, before anything changed.
    if (!s.evalScript) throw Error("the viewer needs a Tcl interpreter", {"UNSUPPORTED", "TK"});
    Session::ScriptResult tk = s.evalScript("package require Tk 8.6");
    if (!tk.ok) {
      throw Error("can't open the viewer: " + tk.result +
                      " (the viewer needs Tk on an X display: set DISPLAY, or run under "
                      "xvfb-run; everything else works without it)",
                  {"UNSUPPORTED", "DISPLAY"});
    }
  });
  open.run([](Call& c) -> Value {
    Session& s = session(c);
    loadViewer(s);
    evalOrThrow(s,
                "::demlab::viewer::Open " + c.str("size") + " " + formatReal(c.real("fps")) + " " +
                    c.str("color") + " " + (c.get<bool>("legend") ? "1" : "0") + " " +
                    (c.get<bool>("timestamp") ? "1" : "0"),
                {"TK"});
    // During runs: a redraw when 1/fps seconds of wall-clock time have passed since the last,
    // and at least 19 times the last redraw's own time: the window takes at most a twentieth
    // of a run however large the scene (a frame of a million grains takes a good part of a
    // second to draw).
    const double period = 1 / c.real("fps");
    using Clock = std::chrono::steady_clock;
    auto next = std::make_shared<Clock::time_point>();
    s.runWatch = [&s, period, next] {
      const auto start = Clock::now();
      if (start < *next) return;
      s.evalScript("::demlab::viewer::Tick");
      const auto end = Clock::now();
      const double took = std::chrono::duration<double>(end - start).count();
      *next = end + std::chrono::duration_cast<Clock::duration>(
                        std::chrono::duration<double>(std::max(period - took, 19 * took)));
    };
    return Value(".demlab_viewer");
  });

  Command& close = r.add("viewer close", "Closes the viewer window; returns 1 if one was open.");
  close.needsScene = false;
  close.changesScene = false;
  close.run([](Call& c) -> Value {
    Session& s = session(c);
    s.runWatch = nullptr;
    if (!viewerLoaded(s)) return Value(false);
    return Value(evalText(s, "::demlab::viewer::Close") == "1");
  });

  Command& sel = r.add("viewer selection",
                       "Returns the ids of the elements selected in the viewer; with elements "
                       "given, selects those first.");
  sel.details =
      "The selection is what a click in the window picked, for use at the console: `element "
      "get [lindex [viewer selection] 0]`. Ids of elements removed since are left out.";
  sel.variadicArg("element", elementRef(), "element ids or names to select").optional = true;
  sel.flag("clear", "select nothing first");
  sel.changesScene = false;
  sel.run([](Call& c) -> Value {
    Session& s = session(c);
    loadViewer(s);
    if (c.flag("clear")) evalOrThrow(s, "::demlab::viewer::Select {}", {"TK"});
    if (c.given("element")) {
      std::string ids;
      for (sim::ElementId id : c.all<sim::ElementId>("element"))
        ids.append(1, ' ').append(std::to_string(scriptId(id)));
      evalOrThrow(s, "::demlab::viewer::Select [list" + ids + "] 1", {"TK"});
    }
    List out;
    const sim::Simulation& sim = s.scene();
    for (const std::string& w : splitList(evalText(s, "set ::demlab::viewer::selection"))) {
      const std::int64_t id = std::atoll(w.c_str());
      try {
        sim.element(fromScriptId<sim::ElementId>(id));
        out.emplace_back(id);
      } catch (const Error&) {
      }
    }
    return Value(std::move(out));
  });

  Command& frame = r.add("viewer frame",
                         "Returns the frame of the scene as a binary PPM image (for a Tk photo).");
  frame.details =
      "Takes the drawing options of \"snapshot write\"; `image create photo -data [viewer frame] "
      "-format ppm` shows it. The bytes are P6 with maxval 255.";
  drawingQuery(frame, [](Call& c, const SnapOptions& o) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    const render::Image img = renderFrame(session(c).scene(), o);
    const std::string head =
        "P6\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n255\n";
    Bytes b;
    b.data.reserve(head.size() + size_t(3) * img.width * img.height);
    b.data.assign(head.begin(), head.end());
    for (size_t k = 0; k < img.rgba.size(); k += 4)
      b.data.insert(b.data.end(), img.rgba.begin() + long(k), img.rgba.begin() + long(k) + 3);
    return Value(std::move(b));
#else
    (void)c, (void)o;
    unsupported();
#endif
  });

  Command& pick = r.add("viewer pick",
                        "Returns the id of the element a pixel of the frame shows, or an empty "
                        "string.");
  pick.details =
      "Takes the drawing options of \"snapshot write\" (the same frame as \"viewer frame\" with "
      "them). The pixel's ray is met with every drawn element as drawn (spheres and discs "
      "exactly, other shapes by their triangles); walls, the background, the title and legend "
      "strips give an empty string.";
  pick.arg("x", integer().min(0), "pixel column, from the left");
  pick.arg("y", integer().min(0), "pixel row, from the top");
  drawingQuery(pick, [](Call& c, const SnapOptions& o) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    if (c.integer("x") >= o.width || c.integer("y") >= o.height) return Value("");
    const std::int64_t id =
        pickFrame(session(c).scene(), o, int(c.integer("x")), int(c.integer("y")));
    return id < 0 ? Value("") : Value(id);
#else
    (void)c, (void)o;
    unsupported();
#endif
  });

  Command& camera = r.add("viewer camera",
                          "Returns the camera a frame is seen with as a dict, the automatic one "
                          "resolved.");
  camera.details =
      "Takes the drawing options of \"snapshot write\". Keys: position, lookat, up (unit), fov "
      "(degrees), viewheight (the world height the frame's scene part shows at the point looked "
      "at: orthographic views, 2D), orthographic (0 or 1).";
  drawingQuery(camera, [](Call& c, const SnapOptions& o) -> Value {
#ifdef DEMLAB_HAVE_RENDER
    const FrameCamera f = frameCamera(session(c).scene(), o);
    auto v = [](const sim::Vec3d& a) { return Value(Reals{{a[0], a[1], a[2]}, 0}); };
    return Value(Dict{{"position", v(f.position)},
                      {"lookat", v(f.lookAt)},
                      {"up", v(f.up)},
                      {"fov", f.fov},
                      {"viewheight", f.viewHeight},
                      {"orthographic", f.orthographic}});
#else
    (void)c, (void)o;
    unsupported();
#endif
  });

  Command& changes = r.add("viewer changes",
                           "Returns a count that grows whenever a command may have changed the "
                           "scene.");
  changes.details =
      "The viewer redraws when it moves (it asks a few times a second while idle); a script "
      "can use it the same way. Every command declared to change the scene counts once when "
      "it runs, whether or not it changed anything.";
  changes.needsScene = false;
  changes.changesScene = false;
  changes.run([](Call& c) -> Value { return Value(std::int64_t(session(c).changes)); });

  Command& stop = r.add("viewer stop",
                        "Asks a run in progress to stop at the next step boundary (the "
                        "viewer's pause button); returns 1 if a run was asked.");
  stop.needsScene = false;
  stop.changesScene = false;
  stop.run([](Call& c) -> Value {
    Session& s = session(c);
    if (!s.running) return Value(false);
    s.stop = true;
    return Value(true);
  });
}

}  // namespace demlab::cmd
