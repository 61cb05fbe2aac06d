// The "behavior" group: one `behavior add TYPE` per type of the behavior registry
// (sim/behavior_registry.hpp), listed, shown and removed by id. Gravity and loads keep their own
// declarations (a default g; components that are Tcl expressions in $t); every other type's
// command is built from the options its registry row declares.
#include "cmd/commands/commands.hpp"
#include "cmd/time_vector.hpp"
#include "cmd/words.hpp"
#include "core/validity.hpp"

namespace demlab::cmd {

namespace {

const TimeBound kLoadBound{validity::kMaxCoefficient, "load", "the loads' bound"};

// Returns the pipe reading a registry option of kind k.
PipeType optionPipe(sim::BehaviorParamKind k) {
  switch (k) {
    case sim::BehaviorParamKind::Number:
      return real();
    case sim::BehaviorParamKind::Vector:
      return vector();
    case sim::BehaviorParamKind::Angular:
      return spin();
    case sim::BehaviorParamKind::Element:
      return elementRef();
    case sim::BehaviorParamKind::Tag:
      return tagName();
  }
  return text();
}

// Declares `behavior add NAME` from the registry row t: one option per declared option, the
// element/tag pair exclusive when the type is targeted; its run hands the named parameters to
// Simulation::addBehavior, which checks them all before it changes anything.
void declareFromRegistry(Registry& r, const sim::BehaviorTypeInfo& t) {
  Command& c = r.add("behavior add " + t.name, "Adds " + t.summary + ".");
  for (const sim::BehaviorOption& o : t.options) {
    PipeType p = optionPipe(o.kind);
    if (!o.unit.empty()) p = p.withUnit(o.unit);
    Param& q = c.option(o.name, p, o.help);
    if (o.required) q.require();
  }
  if (t.targeted) c.oneOf({"element", "tag"}, true);
  // (A distributed scene: the element's owner answers whether it exists, to every rank; a
  // type its step cannot apply is refused on every rank.)
  c.onRanks = OnRanks::Collective;
  c.run([t](Call& c) {
    std::vector<sim::BehaviorParam> ps;
    for (const sim::BehaviorOption& o : t.options) {
      if (!c.given(o.name)) continue;
      sim::BehaviorParam p;
      p.name = o.name;
      switch (o.kind) {
        case sim::BehaviorParamKind::Number:
          p.numbers = {c.real(o.name)};
          break;
        case sim::BehaviorParamKind::Vector:
        case sim::BehaviorParamKind::Angular: {
          const sim::Vec3d v = vec3(c.vec(o.name), o.kind == sim::BehaviorParamKind::Angular);
          p.numbers = {v[0], v[1], v[2]};
          break;
        }
        case sim::BehaviorParamKind::Element:
          p.grain = c.get<sim::ElementId>(o.name);
          break;
        case sim::BehaviorParamKind::Tag:
          p.text = c.str(o.name);
          break;
      }
      ps.push_back(std::move(p));
    }
    try {
      return Value(scriptId(session(c).scene().addBehavior(t.name, ps)));
    } catch (const Error& e) {
      for (const sim::BehaviorParam& p : ps) {
        if (!p.grain.isNull()) rethrowLookup(e, "element", scriptId(p.grain));
      }
      throw;
    }
  });
}

// Returns the parameters of a behavior of type kind as a dict, values spelled as its command
// takes them.
Value paramsValue(const std::string& kind, const std::vector<sim::BehaviorParam>& ps, int dim) {
  Dict d;
  const sim::BehaviorTypeInfo* t = nullptr;
  for (const auto& x : sim::behaviorTypes()) {
    if (x.name == kind) t = &x;
  }
  for (const sim::BehaviorParam& p : ps) {
    auto k = sim::BehaviorParamKind::Number;
    if (t) {
      for (const auto& o : t->options) {
        if (o.name == p.name) k = o.kind;
      }
    }
    if (k == sim::BehaviorParamKind::Element) {
      d.emplace_back(p.name, Value(scriptId(p.grain)));
    } else if (k == sim::BehaviorParamKind::Tag) {
      d.emplace_back(p.name, Value(p.text));
    } else if (p.numbers.size() == 3) {
      d.emplace_back(p.name, vecValue({p.numbers[0], p.numbers[1], p.numbers[2]}, dim,
                                      k == sim::BehaviorParamKind::Angular));
    } else if (p.numbers.size() == 1) {
      d.emplace_back(p.name, Value(p.numbers[0]));
    }
  }
  return Value(d);
}

}  // namespace

void registerBehaviorCommands(Registry& r) {
  std::string types;
  for (const auto& t : sim::behaviorTypes()) types += (types.empty() ? "" : ", ") + t.name;
  r.describe("behavior", "Behaviors: forces and torques applied at every step (" + types + ").");
  r.describe("behavior add", "Adds a behavior of a registered type (" + types +
                                 "); returns its id.");

  Command& g = r.add("behavior add gravity", "Adds uniform gravity on every element.");
  g.onRanks = OnRanks::Collective;  // (the ledger's potential is summed over the ranks)
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
      "Every component, given or computed, must be within 1e30 in magnitude; an expression that "
      "fails or gives more (or a non-finite value) during a run undoes that run (DEMLAB "
      "CALLBACK). Loads with expressions cannot be saved in a checkpoint (see sim save "
      "-skipcallbacks).";
  load.onRanks = OnRanks::Collective;  // (the element's owner answers whether it exists)
  load.option("element", elementRef(), "the element");
  load.option("tag", tagName(), "every element carrying this tag (evaluated at each step)");
  load.oneOf({"element", "tag"}, true);
  load.option("force", timeVector(false).withUnit("N"), "force on each element");
  load.option("torque", timeVector(true).withUnit("N m"),
              "torque on each element (a number in 2D)");
  load.onCheck([](Call& c) {
    sim::LoadDef d;
    if (c.given("element"))
      d.grain = c.get<sim::ElementId>("element");
    else
      d.tag = c.str("tag");
    if (c.has("force")) timeComponents(c, "force", false, kLoadBound, d.force, d.forceFn, false);
    if (c.has("torque"))
      timeComponents(c, "torque", true, kLoadBound, d.torque, d.torqueFn, false);
    c.prepared = d;
  });
  load.run([](Call& c) {
    const auto& d = std::any_cast<const sim::LoadDef&>(c.prepared);
    try {
      return Value(scriptId(session(c).scene().addLoad(d)));
    } catch (const Error& e) {
      if (d.grain.isNull()) throw;
      rethrowLookup(e, "element", scriptId(d.grain));
    }
  });

  for (const auto& t : sim::behaviorTypes()) {
    if (t.name != "gravity" && t.name != "load") declareFromRegistry(r, t);
  }

  Command& list = r.add("behavior list",
                        "Returns the behaviors as a list of dicts {id kind description saveable}.");
  list.onRanks = OnRanks::Alike;
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (const auto& b : session(c).scene().behaviors()) {
      l.emplace_back(Dict{{"id", scriptId(b.id)},
                          {"kind", b.kind},
                          {"description", b.description},
                          {"saveable", b.serializable}});
    }
    return Value(std::move(l));
  });

  Command& info = r.add("behavior info",
                        "Returns a dict {id kind description saveable params} for one behavior.");
  info.onRanks = OnRanks::Alike;
  info.changesScene = false;
  info.arg("behavior", behaviorRef(), "a behavior id");
  info.run([](Call& c) {
    auto& s = session(c).scene();
    const sim::BehaviorId id = c.get<sim::BehaviorId>("behavior");
    for (const auto& b : s.behaviors()) {
      if (b.id != id) continue;
      return Value(Dict{{"id", scriptId(b.id)},
                        {"kind", b.kind},
                        {"description", b.description},
                        {"saveable", b.serializable},
                        {"params", paramsValue(b.kind, b.params, s.dim())}});
    }
    return Value();
  });

  Command& rm = r.add("behavior remove", "Removes a behavior.");
  rm.onRanks = OnRanks::Collective;
  rm.arg("behavior", behaviorRef(), "a behavior id");
  rm.run([](Call& c) {
    session(c).scene().removeBehavior(c.get<sim::BehaviorId>("behavior"));
    return Value();
  });
}

}  // namespace demlab::cmd
