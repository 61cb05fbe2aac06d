// The "periodic" group: periodic boundaries on any axes of the scene, and Lees-Edwards
// (sliding periodic) boundaries for simple shear (sim/periodic.hpp). The Def is checked by the
// scene before anything changes.
#include <string>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

const char* const kAxes[] = {"x", "y", "z"};

// Returns the index of axis word w (x y z) of a dim-dimensional scene. Throws {VALUE AXES}.
int axisIndex(const std::string& w, int dim) {
  for (int k = 0; k < dim; ++k)
    if (w == kAxes[k]) return k;
  throw Error("bad axis \"" + w + "\": must be " + (dim == 2 ? "x or y" : "x, y or z"),
              {"VALUE", "AXES"});
}

Dict periodicDict(const sim::PeriodicDef& p, int dim) {
  List axes;
  for (int k = 0; k < dim; ++k)
    if ((p.axes >> k) & 1u) axes.emplace_back(std::string(kAxes[k]));
  return {{"axes", axes},
          {"lo", vecValue(p.lo, dim)},
          {"hi", vecValue(p.hi, dim)},
          {"shear", p.shearRate},
          {"flow", std::string(kAxes[p.flow])},
          {"gradient", std::string(kAxes[p.gradient])},
          {"offset", p.offset}};
}

}  // namespace

void registerPeriodicCommands(Registry& r) {
  r.describe("periodic",
             "Periodic boundaries: the scene repeats along chosen axes; Lees-Edwards boundaries "
             "shear it.");

  Command& set = r.add(
      "periodic set",
      "Makes the axes periodic with the cell lo..hi, from the next step on: every pair is "
      "measured to the nearest image, and elements leaving the cell re-enter on the other side "
      "at the next neighbour search. With -shear, Lees-Edwards boundaries: the images one cell "
      "up the gradient axis move along the flow axis at rate x cell height (simple shear). Each "
      "periodic length must exceed twice the largest pair reach (two radii and the skin).");
  set.option("axes", text("list of axes").asList(), "the periodic axes, a list of x, y, z")
      .require();
  set.option("lo", vector().withUnit("m"), "the cell's lower corner").require();
  set.option("hi", vector().withUnit("m"), "the cell's upper corner").require();
  set.option("shear", real().withUnit("1/s"),
             "Lees-Edwards shear rate, d(flow velocity)/d(gradient) (default 0: none)");
  set.option("flow", choice({"x", "y", "z"}), "the shear's flow axis").byDefault("x");
  set.option("gradient", choice({"x", "y", "z"}), "the shear's gradient axis").byDefault("y");
  set.onCheck([](Call& c) {
    const int dim = session(c).scene().dim();
    sim::PeriodicDef d;
    for (const std::string& w : splitList(c.str("axes"))) {
      const int k = axisIndex(w, dim);
      if ((d.axes >> k) & 1u) c.bad("axes", "names axis " + w + " twice");
      d.axes |= 1u << k;
    }
    if (d.axes == 0) c.bad("axes", "must name at least one axis (\"periodic clear\" removes them)");
    d.lo = vec3(c.vec("lo"));
    d.hi = vec3(c.vec("hi"));
    if (c.has("shear")) d.shearRate = c.real("shear");
    d.flow = axisIndex(c.str("flow"), dim);
    d.gradient = axisIndex(c.str("gradient"), dim);
    c.prepared = d;
  });
  set.run([](Call& c) {
    session(c).scene().setPeriodic(std::any_cast<sim::PeriodicDef>(c.prepared));
    return Value();
  });

  Command& get = r.add("periodic get",
                       "Returns the periodic cell as a dict (axes, lo, hi, shear, flow, gradient, "
                       "offset: the Lees-Edwards images' displacement now), or the field asked "
                       "for; axes is empty when nothing is periodic.");
  for (const char* f : {"axes", "lo", "hi", "shear", "flow", "gradient", "offset"})
    get.flag(f, std::string("the ") + f);
  get.changesScene = false;
  get.run([](Call& c) {
    const auto& s = session(c).scene();
    return pickFields(c, periodicDict(s.periodic(), s.dim()));
  });

  Command& clear = r.add("periodic clear",
                         "Removes the periodic boundaries (elements stay where they are).");
  clear.run([](Call& c) {
    session(c).scene().setPeriodic(sim::PeriodicDef{});
    return Value();
  });
}

}  // namespace demlab::cmd
