// The "behavior" group: gravity and loads (constant, or functions of time written as Tcl
// expressions in $t), listed and removed by id.
#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

// A vector whose components are numbers or Tcl expressions in $t; value: the words. The
// expressions are compiled and tried in the check phase (see Session::timeFunction).
PipeType loadVector(bool isSpin) {
  return custom(isSpin ? "spin of expressions" : "vector of expressions",
                [isSpin](std::string_view w, const Param& p, const Context& c) -> std::any {
                  std::vector<std::string> parts;
                  try {
                    parts = splitList(w);
                  } catch (const Error& e) {
                    throw Error(e.what(), {"VALUE", codeWord(p.name)});
                  }
                  std::size_t n =
                      isSpin ? (c.dimension() == 2 ? 1 : 3) : std::size_t(c.dimension());
                  if (parts.size() != n) {
                    throw Error("bad " + p.name + " \"" + std::string(w) + "\": expected " +
                                    std::to_string(n) + " numbers or expressions in $t but got " +
                                    std::to_string(parts.size()),
                                {"VALUE", codeWord(p.name)});
                  }
                  return parts;
                });
}

// Fills the constants and time functions of one load vector into `constant` and `fns`.
void loadComponents(Call& c, const std::string& opt, bool isSpin, sim::Vec3d& constant,
                    std::array<sim::TimeFunction, 3>& fns) {
  Session& s = session(c);
  const auto& parts = c.get<std::vector<std::string>>(opt);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    std::size_t axis = isSpin && parts.size() == 1 ? 2 : k;
    double x;
    if (readReal(parts[k], x)) {
      if (!std::isfinite(x)) c.bad(opt, "must be finite");
      constant[axis] = x;
    } else {
      if (!s.timeFunction)
        throw Error("bad " + opt + ": expressions need a Tcl interpreter",
                    {"VALUE", codeWord(opt)});
      fns[axis] = s.timeFunction(parts[k], opt, s.scene().time());
    }
  }
}

}  // namespace

void registerBehaviorCommands(Registry& r) {
  r.describe("behavior", "Behaviors: gravity and loads applied at every step.");
  r.describe("behavior add", "Adds a behavior; returns its id.");

  Command& g = r.add("behavior add gravity", "Adds uniform gravity on every element.");
  g.option("g", vector().withUnit("m/s^2"), "the acceleration (default: 9.81 down the last axis)");
  g.run([](Call& c) {
    auto& s = session(c).scene();
    sim::Vec3d acc{0, 0, 0};
    if (c.has("g"))
      acc = vec3(c.vec("g"));
    else
      acc[std::size_t(s.dim() - 1)] = -9.81;
    return Value(scriptId(s.addGravity(acc)));
  });

  Command& load = r.add("behavior add load",
                        "Adds a force and torque on one element or on every element of a tag.");
  load.details =
      "Each component is a number or a Tcl expression in $t (the simulated time, s), e.g. "
      "-force {0 0 {-2.0*sin(50*$t)}}; an expression is evaluated at every step, so keep it cheap. "
      "Loads with expressions cannot be saved in a checkpoint (see sim save -skipcallbacks).";
  load.option("element", elementRef(), "the element");
  load.option("tag", tagName(), "every element carrying this tag (evaluated at each step)");
  load.oneOf({"element", "tag"}, true);
  load.option("force", loadVector(false).withUnit("N"), "force on each element");
  load.option("torque", loadVector(true).withUnit("N m"),
              "torque on each element (a number in 2D)");
  load.onCheck([](Call& c) {
    sim::LoadDef d;
    if (c.given("element"))
      d.grain = c.get<sim::GrainId>("element");
    else
      d.tag = c.str("tag");
    if (c.has("force")) loadComponents(c, "force", false, d.force, d.forceFn);
    if (c.has("torque")) loadComponents(c, "torque", true, d.torque, d.torqueFn);
    c.prepared = d;
  });
  load.run([](Call& c) {
    return Value(scriptId(session(c).scene().addLoad(std::any_cast<sim::LoadDef>(c.prepared))));
  });

  Command& list = r.add("behavior list",
                        "Returns the behaviors as a list of dicts {id kind description saveable}.");
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (const auto& b : session(c).scene().behaviors()) {
      l.emplace_back(Dict{{"id", scriptId(b.id)},
                          {"kind", b.kind},
                          {"description", b.description},
                          {"saveable", b.serializable}});
    }
    return Value(l);
  });

  Command& rm = r.add("behavior remove", "Removes a behavior.");
  rm.arg("behavior", behaviorRef(), "a behavior id");
  rm.run([](Call& c) {
    session(c).scene().removeBehavior(c.get<sim::BehaviorId>("behavior"));
    return Value();
  });
}

}  // namespace demlab::cmd
