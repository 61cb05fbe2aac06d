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

  Command& touch = r.add("module touch",
                         "Turns the sub-step treatment of contact onset and release on or off, or "
                         "returns whether it is on.");
  touch.details =
      "Off by default. On, the step in which a contact's normal force begins or ends (a touch, "
      "a release, a damped force reaching its cut-off) receives the integral of the force over "
      "the part of the step the force acted instead of the trapezoid's half step, and the energy "
      "ledger books the damper's loss to match: impacts become second order in the time step "
      "whatever the phase of the touch, and the energy of an elastic gas stops wandering by "
      "O(dt^2) per collision (doc/design.md, \"Touch and release\"). The tangential force is "
      "not corrected. LIGGGHTS has no such correction: leave it off to reproduce LIGGGHTS. "
      "Part of the scene (saved with it).";
  touch.optionalArg("on", boolean(), "a boolean");
  touch.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("on")) s.setTouchCorrection(c.get<bool>("on"));
    return Value(s.touchCorrection());
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

  Command& wd = r.add("module watchdog",
                      "Sets the watchdog's options (on by default); returns them as a dict.");
  wd.details =
      "After every step (and before the first step of a run) the watchdog checks that no "
      "position or velocity is non-finite (NAN), no element moves more in one step than the "
      "neighbour search tracks, half the skin (SPEED), no contact overlaps by more than a "
      "fraction of the smaller radius (OVERLAP; another fraction, -placed, for the scene as "
      "set up, before its first step) and the energy balance has not grown by more "
      "than a fraction of the energy scale (ENERGY). When one fails the run stops at that step "
      "with the error DEMLAB WATCHDOG <check>, naming the elements, the likely cause and the "
      "fix. The options are part of the scene (saved with it).";
  wd.option("on", boolean(), "run the watchdog (default 1)").to(&sim::WatchdogOptions::enabled);
  wd.option("overlap", real().nonNegative(),
            "largest overlap during a run, as a fraction of the smaller radius (default 2: a "
            "grain gone through another; 0.2 suits stiff materials; 0: no check)")
      .to(&sim::WatchdogOptions::overlap);
  wd.option("placed", real().nonNegative(),
            "largest overlap of the scene as set up, checked before its first step (default "
            "0.5; 0: no check)")
      .to(&sim::WatchdogOptions::placed);
  wd.option("energy", real().nonNegative(),
            "largest growth of the energy balance as a fraction of the energy scale (default "
            "0.5; 0: no check)")
      .to(&sim::WatchdogOptions::energy);
  wd.option("speed", boolean(), "check that no element outruns the skin (default 1)")
      .to(&sim::WatchdogOptions::speed);
  wd.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("on") || c.given("overlap") || c.given("placed") || c.given("energy") ||
        c.given("speed")) {
      sim::WatchdogOptions o = s.watchdog();
      c.fill(o);
      s.setWatchdog(o);
    }
    sim::WatchdogOptions o = s.watchdog();
    return Value(Dict{{"on", o.enabled},
                      {"overlap", o.overlap},
                      {"placed", o.placed},
                      {"energy", o.energy},
                      {"speed", o.speed}});
  });
}

}  // namespace demlab::cmd
