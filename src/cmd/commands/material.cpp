// The "material" and "law" groups: materials by name, and the contact law used by each pair.
#include <cmath>

#include <limits>

#include "cmd/commands/commands.hpp"
#include "cmd/commands/option_commands.hpp"
#include "physics/pair_params.hpp"

namespace demlab::cmd {

namespace {

using physics::MaterialDef;

// Declares the material properties on c, bound to MaterialDef's fields; required when adding.
void materialOptions(Command& c, bool required) {
  auto opt = [&](const char* n, PipeType t, const char* help, double MaterialDef::*m,
                 bool req) -> Param& {
    Param& p = c.option(n, std::move(t), help).to(m);
    if (req && required) p.require();
    return p;
  };
  opt("density", real().positive().withUnit("kg/m^3"), "mass density (kg/m^2 for 2D discs)",
      &MaterialDef::density, true);
  opt("young", real().positive().withUnit("Pa"), "Young's modulus (required unless -rigid 1)",
      &MaterialDef::young, false);
  opt("poisson", real().min(-1, true).max(0.5, true), "Poisson's ratio", &MaterialDef::poisson,
      true);
  opt("restitution", real().min(0, true).max(1), "normal coefficient of restitution",
      &MaterialDef::restitution, true);
  opt("friction", real().nonNegative(), "Coulomb friction coefficient", &MaterialDef::friction,
      true);
  opt("rolling", real().nonNegative(),
      "rolling friction: the resisting couple's lever arm per unit radius (0: none)",
      &MaterialDef::rollingFriction, false);
  opt("cohesion", real().nonNegative().withUnit("Pa"),
      "cohesion: overlapping surfaces attract with it times their contact area (0: none)",
      &MaterialDef::cohesion, false);
  opt("normalstiffness", real().nonNegative().withUnit("N/m"),
      "linear law: normal spring (0: from young)", &MaterialDef::normalStiffness, false);
  opt("shearstiffness", real().nonNegative().withUnit("N/m"),
      "linear law: shear spring (0: from the normal one)", &MaterialDef::shearStiffness, false);
  c.option("rigid", boolean(),
           "1: infinitely stiff, for walls: a pair with it takes its moduli from the other "
           "material alone (a wall of an ordinary material is an elastic half-space of it)");
}

// Returns nothing; applies -rigid and -young of call c to d (a rigid material's modulus is
// +Inf). Throws {ARGS} when adding without either, {VALUE RIGID} for -rigid 1 with -young or
// -rigid 0 on a rigid material without -young.
void applyRigid(const Call& c, MaterialDef& d, bool adding) {
  const bool given = c.given("rigid"), rigid = given && c.get<bool>("rigid");
  if (rigid && c.given("young")) {
    throw Error("-rigid 1 and -young can't be given together: a rigid material has no modulus",
                {"VALUE", "RIGID"});
  }
  if (rigid) d.young = std::numeric_limits<double>::infinity();
  if (given && !rigid && d.isRigid() && !c.given("young")) {
    throw Error("a material made elastic with -rigid 0 needs -young", {"VALUE", "RIGID"});
  }
  if (adding && !rigid && !c.given("young")) {
    throw Error("missing required option -young: should be \"" + c.command().usage() + "\"",
                {"ARGS"});
  }
}

const char* const kFields[] = {"density",     "young",           "poisson",
                               "restitution", "friction",        "rolling",
                               "cohesion",    "normalstiffness", "shearstiffness",
                               "rigid"};

Dict materialDict(const MaterialDef& m) {
  return {{"density", m.density},
          {"young", m.young},
          {"poisson", m.poisson},
          {"restitution", m.restitution},
          {"friction", m.friction},
          {"rolling", m.rollingFriction},
          {"cohesion", m.cohesion},
          {"normalstiffness", m.normalStiffness},
          {"shearstiffness", m.shearStiffness},
          {"rigid", static_cast<int64_t>(m.isRigid())}};
}

std::string lawWord(physics::LawKind k) {
  return std::string(physics::lawName(k));
}

}  // namespace

namespace {

// The coefficients a pair of materials may have of its own (`law coefficients`), one row each:
// the option, the API's field, its range and its help.
struct PairField {
  const char* name;
  double sim::PairCoefficients::*field;
  PipeType (*spec)();
  const char* help;
};
const PairField kPairFields[] = {
    {"restitution", &sim::PairCoefficients::restitution,
     [] { return real().min(0, true).max(1); }, "the pair's restitution"},
    {"friction", &sim::PairCoefficients::friction, [] { return real().nonNegative(); },
     "the pair's Coulomb friction"},
    {"rolling", &sim::PairCoefficients::rolling, [] { return real().nonNegative(); },
     "the pair's rolling friction"},
    {"cohesion", &sim::PairCoefficients::cohesion,
     [] { return real().nonNegative().withUnit("Pa"); }, "the pair's cohesion"},
    {"young", &sim::PairCoefficients::young, [] { return real().positive().withUnit("Pa"); },
     "the pair's effective Young's modulus E* = 1 / ((1 - nu_a^2) / E_a + (1 - nu_b^2) / E_b), "
     "which sets both laws' normal stiffness (the shear modulus follows with the Poisson "
     "ratios)"},
};

}  // namespace

void registerMaterialCommands(Registry& r) {
  r.describe("material", "Materials: named sets of constants that elements and walls refer to.");

  Command& add = r.add("material add", "Defines a material.");
  add.arg("name", name("name"), "the material's name (a letter or _ first)");
  materialOptions(add, true);
  add.onCheck([](Call& c) {
    auto names = session(c).scene().materialNames();
    if (std::find(names.begin(), names.end(), c.str("name")) != names.end()) {
      throw Error("material \"" + c.str("name") + "\" already exists", {"EXISTS", "MATERIAL"});
    }
    MaterialDef d;
    c.fill(d);
    applyRigid(c, d, true);
    d.check();
    c.prepared = d;
  });
  add.run([](Call& c) {
    session(c).scene().addMaterial(c.str("name"), std::any_cast<MaterialDef>(c.prepared));
    return Value(c.str("name"));
  });

  Command& set = r.add("material set",
                       "Changes some constants of a material (element masses follow the density).");
  set.arg("name", materialRef(), "an existing material");
  set.onRanks = OnRanks::Collective;  // (every rank's elements take the new density)
  materialOptions(set, false);
  set.onCheck([](Call& c) {
    MaterialDef d = session(c).scene().material(c.str("name"));
    c.fill(d);
    applyRigid(c, d, false);
    d.check();
    c.prepared = d;
  });
  set.run([](Call& c) {
    session(c).scene().setMaterial(c.str("name"), std::any_cast<MaterialDef>(c.prepared));
    return Value();
  });

  Command& get = r.add("material get", "Returns a material's constants as a dict, or one of them.");
  get.onRanks = OnRanks::Alike;
  get.arg("name", materialRef(), "an existing material");
  for (const char* f : kFields) get.flag(f, std::string("return the ") + f + " alone");
  get.changesScene = false;
  get.run([](Call& c) {
    Dict d = materialDict(session(c).scene().material(c.str("name")));
    if (c.flagOrder().empty()) return Value(d);
    Dict picked;
    for (const std::string& f : c.flagOrder())
      for (auto& kv : d)
        if (kv.first == f) picked.push_back(kv);
    if (picked.size() == 1) return picked[0].second;
    return Value(picked);
  });

  Command& list = r.add("material list", "Returns the names of the materials, in creation order.");
  list.onRanks = OnRanks::Alike;
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (auto& n : session(c).scene().materialNames()) l.emplace_back(n);
    return Value(std::move(l));
  });

  r.describe("law",
             "Contact laws: the default law, its sub-models, the law of a pair of materials and "
             "its coefficients.");
  Command& def =
      r.add("law default", "Sets the law of every pair without its own law, or returns it.");
  def.optionalArg("law", lawChoice(), "linear or hertz_mindlin (prefixes accepted)");
  def.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("law")) s.setContactLaw(c.get<physics::LawKind>("law"));
    return Value(lawWord(s.contactLaw()));
  });

  Command& coulomb =
      r.add("law coulomb", "Sets what the Coulomb limit caps in every pair, or returns it.");
  coulomb.details =
      "total (the default): the whole tangential force, spring and dashpot, never exceeds mu Fn, "
      "as in LAMMPS's granular models and MercuryDPM; spring: only the spring force is compared "
      "with mu Fn, so the dashpot may exceed it while a contact sticks (LIGGGHTS's tangential "
      "history, kept to reproduce LIGGGHTS runs).";
  coulomb.optionalArg("criterion", choice({"total", "spring"}), "total or spring");
  coulomb.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("criterion")) {
      s.setCoulombCriterion(c.str("criterion") == "total" ? physics::CoulombCriterion::Total
                                                          : physics::CoulombCriterion::Spring);
    }
    return Value(std::string(physics::coulombCriterionName(s.coulombCriterion())));
  });

  Command& damping = r.add(
      "law damping", "Sets how Hertz-Mindlin's restitution becomes its damping, or returns it.");
  damping.details =
      "calibrated (the default): the damper's beta is solved from the cut-off Hertz impact so "
      "that a head-on impact rebounds with the pair's restitution e; liggghts: LIGGGHTS's beta = "
      "ln e / sqrt(ln^2 e + pi^2), whose rebound exceeds e once the attractive force is cut off "
      "(0.25 for e = 0.1, 0.55 for e = 0.5), kept to reproduce LIGGGHTS runs. The linear law "
      "always rebounds with e.";
  damping.optionalArg("form", choice({"calibrated", "liggghts"}), "calibrated or liggghts");
  damping.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("form")) {
      s.setHertzDamping(c.str("form") == "calibrated" ? physics::HertzDamping::Calibrated
                                                      : physics::HertzDamping::Liggghts);
    }
    return Value(std::string(physics::hertzDampingName(s.hertzDamping())));
  });

  // The sub-models: -normal and -damping are law default's and law damping's choices, the
  // others the option table's "law" rows (sim/options.hpp).
  const sim::OptionGroup& models = sim::findOptionGroup("law");
  Command& model = r.add("law model", std::string(models.summary));
  model.details = std::string(models.details);
  model.option("normal", choice({"linear", "hertz"}),
               "the law of every pair without its own: linear or hertz (Hertz-Mindlin)");
  model.option("damping", choice({"calibrated", "liggghts"}),
               "Hertz-Mindlin's damping: calibrated or liggghts (law damping)");
  addOptionParams(model, "law");
  model.run([](Call& c) {
    auto& s = session(c).scene();
    // Every value was checked by its pipe, so none of these throws once the first has run.
    const auto given = givenOptions(c, "law");
    if (!given.empty()) s.setOptions(given);
    if (c.given("normal")) {
      s.setContactLaw(c.str("normal") == "linear" ? physics::LawKind::Linear
                                                  : physics::LawKind::HertzMindlin);
    }
    if (c.given("damping")) {
      s.setHertzDamping(c.str("damping") == "calibrated" ? physics::HertzDamping::Calibrated
                                                         : physics::HertzDamping::Liggghts);
    }
    Dict d{{"normal", std::string(s.contactLaw() == physics::LawKind::Linear ? "linear" : "hertz")},
           {"damping", std::string(physics::hertzDampingName(s.hertzDamping()))}};
    for (const sim::OptionSpec* o : sim::groupOptions("law")) {
      d.emplace_back(std::string(o->name), optionValue(s.option("law", o->name)));
    }
    return Value(d);
  });

  Command& pair = r.add("law pair", "Sets the law of one pair of materials, or returns it.");
  pair.arg("a", materialRef(), "a material");
  pair.arg("b", materialRef(), "another (or the same) material");
  pair.optionalArg("law", lawChoice(), "linear or hertz_mindlin");
  pair.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("law")) s.setPairLaw(c.str("a"), c.str("b"), c.get<physics::LawKind>("law"));
    return Value(lawWord(s.pairLaw(c.str("a"), c.str("b"))));
  });

  Command& coef = r.add("law coefficients",
                        "Sets coefficients of one pair of materials that replace the mixing "
                        "rules' values, or returns the pair's coefficients.");
  coef.details =
      "The mixing rules: restitution sqrt(e_a e_b), friction, rolling friction and cohesion the "
      "smaller of the two materials', the effective modulus from both moduli and Poisson "
      "ratios. A value given here is the pair's whatever its materials "
      "say (LIGGGHTS's peratomtypepair tables); options not given keep the pair's earlier "
      "values, -reset 1 drops them first. Returns the dict of the pair's coefficients in use "
      "and, under \"own\", the names of those that are the pair's own.";
  coef.arg("a", materialRef(), "a material");
  coef.arg("b", materialRef(), "another (or the same) material");
  for (const PairField& f : kPairFields) coef.option(f.name, f.spec(), f.help);
  coef.option("reset", boolean(), "1: the mixing rules' values for every coefficient not given");
  coef.run([](Call& c) {
    auto& s = session(c).scene();
    const std::string a = c.str("a"), b = c.str("b");
    sim::PairCoefficients own = s.pairOverrides(a, b);
    bool edits = c.given("reset");
    if (c.given("reset") && c.get<bool>("reset")) own = {};
    for (const PairField& f : kPairFields) {
      if (!c.given(f.name)) continue;
      own.*f.field = c.get<double>(f.name);
      edits = true;
    }
    if (edits) s.setPairCoefficients(a, b, own);
    const sim::PairCoefficients used = s.pairCoefficients(a, b);
    Dict out;
    List mine;
    for (const PairField& f : kPairFields) {
      out.emplace_back(f.name, used.*f.field);
      if (!std::isnan(own.*f.field)) mine.emplace_back(std::string(f.name));
    }
    out.emplace_back("own", mine);
    return Value(out);
  });
}

}  // namespace demlab::cmd
