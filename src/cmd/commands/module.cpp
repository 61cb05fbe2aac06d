// The "module" group: the stages of the time step a scene runs, and their options.
#include "cmd/commands/commands.hpp"

namespace demlab::cmd {

void registerModuleCommands(Registry& r) {
  r.describe("module", "The modules of the time step: which run, and their options.");

  Command& list = r.add("module list", "Returns the modules the next step runs, in loop order.");
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (auto& m : session(c).scene().listModules()) l.emplace_back(m);
    return Value(l);
  });

  Command& integ = r.add("module integrator", "Sets the integrator, or returns it.");
  integ.details =
      "synchronized (the default; Vyas et al. 2025, physical for static friction at large size "
      "ratios) "
      "or verlet (plain velocity Verlet, as LAMMPS and LIGGGHTS).";
  integ.optionalArg("name", choice({"synchronized", "verlet"}), "the integrator");
  integ.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("name")) s.setIntegrator(c.str("name"));
    return Value(s.integrator());
  });

  Command& rot =
      r.add("module rotation", "Turns element rotation on or off, or returns whether it is on.");
  rot.optionalArg("on", boolean(), "a boolean");
  rot.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("on")) s.setRotation(c.get<bool>("on"));
    return Value(s.rotation());
  });

  Command& det =
      r.add("module detection", "Sets contact detection (CGrid) options; returns them as a dict.");
  det.option("cellfactor", real().nonNegative(),
             "CGrid cell = factor x size statistic (0: CGrid's default)")
      .to(&sim::DetectionOptions::cellFactor);
  det.option("skin", real().withUnit("m"),
             "Verlet skin (negative: automatic, 0: search every step)")
      .to(&sim::DetectionOptions::skin);
  det.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("cellfactor") || c.given("skin")) {
      sim::DetectionOptions o = s.detection();
      c.fill(o);
      s.setDetection(o);
    }
    sim::DetectionOptions o = s.detection();
    return Value(Dict{{"cellfactor", o.cellFactor}, {"skin", o.skin}});
  });
}

}  // namespace demlab::cmd
