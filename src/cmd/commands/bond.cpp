// The "bond" group: bond models (one `bond model TYPE` per row of the bond model table,
// sim/bond_model.hpp), making bonds (by gap within a region or tag group, by named pairs, from
// a file), listing, querying, removing them and the list of breaks.
#include <limits>
#include <optional>
#include <sstream>

#include "analysis/region_geometry.hpp"
#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/free_aside.hpp"
#include "core/interrupt.hpp"
#include "io/line_reader.hpp"
#include "sim/bond_model.hpp"
#include "sim/packing.hpp"

namespace demlab::cmd {

namespace {

using Pairs = std::vector<std::pair<sim::ElementId, sim::ElementId>>;

// Returns the pairs a list of two-element lists names; each element by id or name.
Pairs readPairs(std::string_view w, const Param& p, const Context& c) {
  Pairs out;
  const PipeType element = elementRef();
  for (const std::string& pair : splitList(w)) {
    const std::vector<std::string> two = splitList(pair);
    if (two.size() != 2) {
      throw Error("bad " + p.name + " \"" + pair + "\": expected two elements",
                  {"VALUE", codeWord(p.name)});
    }
    out.emplace_back(std::any_cast<sim::ElementId>(element.custom(two[0], p, c)),
                     std::any_cast<sim::ElementId>(element.custom(two[1], p, c)));
    if (out.back().first == out.back().second) {
      throw Error("bad " + p.name + " \"" + pair + "\": an element can't be bonded to itself",
                  {"VALUE", codeWord(p.name)});
    }
  }
  return out;
}

// A list of pairs {{a b} {c d} ...} of element ids or names; value: Pairs.
PipeType pairList() {
  return custom("list of element pairs",
                [](std::string_view w, const Param& p, const Context& c) -> std::any {
                  return readPairs(w, p, c);
                });
}

// Declares `bond model TYPE` from the table row t: one option per declared option.
void declareModel(Registry& r, const sim::BondModelType& t) {
  Command& c = r.add("bond model " + t.name, "Defines a bond model: " + t.summary + ".");
  c.details = t.details;
  c.arg("name", name("name"), "the model's name (a letter or _ first)");
  for (const sim::BondOption& o : t.options) {
    PipeType p = real();
    if (!o.unit.empty()) p = p.withUnit(o.unit);
    // A required option says so through require(); help adds the word once.
    Param& q = c.option(o.name, p,
                        std::isnan(o.fallback)
                            ? o.help
                            : o.help + " (default " + physics::formatReal(o.fallback) + ")");
    if (std::isnan(o.fallback)) q.require();
  }
  c.run([t](Call& c) {
    std::vector<std::pair<std::string, double>> values;
    for (const sim::BondOption& o : t.options) {
      if (c.given(o.name)) values.emplace_back(o.name, c.real(o.name));
    }
    session(c).scene().addBondModel(c.str("name"), t.name, values);
    return Value(c.str("name"));
  });
}

// Returns bond ids as a Tcl list.
Value idList(const std::vector<std::uint32_t>& ids) {
  return Ints{{ids.begin(), ids.end()}};
}

// Returns the dict `bond query` gives for b.
Value bondValue(const sim::BondInfo& b, int dim) {
  return Value(Dict{{"id", static_cast<std::int64_t>(b.id)},
                    {"a", scriptId(b.a)},
                    {"b", scriptId(b.b)},
                    {"model", b.model},
                    {"intact", b.intact},
                    {"force", vecValue(b.force, dim)},
                    {"moment", vecValue(b.moment, dim, true)},
                    {"normal", b.normalForce},
                    {"sigma", b.sigma},
                    {"tau", b.tau},
                    {"strain", b.strain},
                    {"length", b.length},
                    {"restlength", b.restLength},
                    {"energy", b.energy},
                    {"tensile", b.tensile},
                    {"shear", b.shear},
                    {"breakmode", b.breakMode},
                    {"breaktime", b.breakTime}});
}

}  // namespace

void registerBondCommands(Registry& r) {
  std::string types;
  for (const auto& t : sim::bondModelTypes()) types += (types.empty() ? "" : ", ") + t.name;
  r.describe("bond",
             "Bonds: cemented pairs of elements that carry force and moment until they "
             "break (" +
                 types + ").");
  r.describe("bond model", "Defines a named set of bond parameters of a type (" + types + ").");
  for (const auto& t : sim::bondModelTypes()) declareModel(r, t);

  Command& models =
      r.add("bond models", "Returns the bond models as a list of dicts {name type values}.");
  models.changesScene = false;
  models.run([](Call& c) {
    List l;
    for (const sim::BondModelInfo& m : session(c).scene().bondModels()) {
      Dict values;
      for (const auto& [k, x] : m.values) values.emplace_back(k, x);
      l.emplace_back(Dict{{"name", m.name}, {"type", m.type}, {"values", values}});
    }
    return Value(std::move(l));
  });

  Command& add = r.add("bond add", "Bonds pairs of elements; returns the new bonds' ids.");
  add.interruptible = true;
  add.details =
      "With -gap, every pair whose surfaces are at most the gap apart (an overlap counts) and "
      "that has no bond yet, among the elements whose centre is in -region and that carry -tag "
      "(both when both are given; every element when neither); with -pairs, the pairs named. "
      "A bond's rest length is the pair's centre distance when it is made. The bond acts beside "
      "the pair's contact law; when it breaks only its own force goes.";
  add.option("model", text("model"), "the bond model (see bond model)").require();
  add.option("gap", real().nonNegative().withUnit("m"),
             "largest surface gap of a bonded pair (at most the largest diameter of the elements)");
  add.option("pairs", pairList(), "the pairs {{a b} ...} (element ids or names)");
  add.oneOf({"gap", "pairs"}, true);
  add.option("region", regionType(), "{box {lo} {hi}} or {sphere {centre} radius}");
  add.option("tag", tagName(), "only the elements carrying this tag");
  add.run([](Call& c) {
    auto& s = session(c).scene();
    std::vector<std::uint32_t> ids;
    if (c.given("pairs")) {
      if (c.given("region") || c.given("tag")) c.bad("pairs", "takes neither -region nor -tag");
      ids = s.addBonds(c.get<Pairs>("pairs"), c.str("model"));
    } else {
      std::vector<sim::ElementId> among;
      const bool select = c.given("region") || c.given("tag");
      if (select) {
        const std::vector<sim::ElementId> all =
            c.given("tag") ? s.elementsTagged(c.str("tag")) : s.elementIds();
        for (sim::ElementId id : all) {
          if (c.given("region") &&
              !analysis::holdsPoint(c.get<sim::Region>("region"), s.element(id).position, s.dim()))
            continue;
          among.push_back(id);
        }
        if (among.empty()) c.bad(c.given("tag") ? "tag" : "region", "selects no element");
      }
      ids = s.addBondsWithin(among, c.real("gap"), c.str("model"));
    }
    return idList(ids);
  });

  Command& file = r.add("bond file", "Bonds the pairs a file lists; returns the new bonds' ids.");
  file.interruptible = true;
  file.details =
      "One pair a line: two element ids or names; blank lines and lines starting "
      "with # are skipped. All or none.";
  file.arg("path", readableFile(), "the file");
  file.option("model", text("model"), "the bond model").require();
  file.run([](Call& c) {
    io::LineReader in(c.str("path"));  // counts lines and polls for Ctrl-C
    Param p;
    p.name = "pair";
    Pairs pairs;
    std::string_view line;
    while (in.next(line)) {
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string_view::npos || line[first] == '#') continue;
      try {
        const Pairs one = readPairs(quoteElement(std::string(line)), p, c.context());
        pairs.insert(pairs.end(), one.begin(), one.end());
      } catch (const Error& e) {
        throw e.within(in.where());
      }
    }
    return idList(session(c).scene().addBonds(pairs, c.str("model")));
  });

  Command& list = r.add("bond list", "Returns the bonds as a list of dicts {id a b model intact}.");
  list.changesScene = false;
  list.run([](Call& c) {
    std::vector<sim::BondInfo> bonds = session(c).scene().bonds();
    List l;
    // Stopped, a million small dicts and the bonds' states are freed on a thread of their own.
    const FreeAsideOnThrow asideBonds(bonds);
    const FreeAsideOnThrow aside(l);
    InterruptPoll poll("bond list");
    for (const sim::BondInfo& b : bonds) {
      poll();
      l.emplace_back(Dict{{"id", static_cast<std::int64_t>(b.id)},
                          {"a", scriptId(b.a)},
                          {"b", scriptId(b.b)},
                          {"model", b.model},
                          {"intact", b.intact}});
    }
    return Value(std::move(l));
  });

  Command& query = r.add("bond query", "Returns one bond's state as a dict.");
  query.details =
      "Keys: id a b model intact, force and moment on b (a takes the opposite), normal (> 0: "
      "tension), sigma and tau (what the strengths are compared with), strain, length, "
      "restlength, energy, tensile and shear (the bond's strengths), breakmode (\"\" while "
      "intact, tension or shear) and breaktime.";
  query.changesScene = false;
  query.arg("bond", integer().nonNegative(), "a bond id");
  query.run([](Call& c) {
    auto& s = session(c).scene();
    const std::int64_t id = c.integer("bond");
    const auto b = id <= std::numeric_limits<std::uint32_t>::max()
                       ? s.bond(static_cast<std::uint32_t>(id))
                       : std::nullopt;
    if (!b) throw Error("no bond " + std::to_string(id), {"LOOKUP", "BOND"});
    return bondValue(*b, s.dim());
  });

  Command& count =
      r.add("bond count", "Returns a dict {bonds intact broken tension shear} of counts.");
  count.changesScene = false;
  count.run([](Call& c) {
    const sim::BondCount n = session(c).scene().bondCount();
    auto i = [](std::uint64_t k) { return static_cast<std::int64_t>(k); };
    return Value(Dict{{"bonds", i(n.bonds)},
                      {"intact", i(n.intact)},
                      {"broken", i(n.bonds - n.intact)},
                      {"tension", i(n.tension)},
                      {"shear", i(n.shear)}});
  });

  Command& breaks = r.add("bond breaks",
                          "Returns the breaks as a list of dicts {bond a b mode time step point "
                          "energy measure}, in the order they happened.");
  breaks.details =
      "point is the bond's centre when it broke; energy the elastic energy it held "
      "(booked in the energy ledger as released); measure the stress (or force) that exceeded the "
      "strength: sigma for tension, tau for shear.";
  breaks.changesScene = false;
  breaks.run([](Call& c) {
    auto& s = session(c).scene();
    List l;
    for (const sim::BondBreakInfo& k : s.bondBreaks()) {
      l.emplace_back(Dict{{"bond", static_cast<std::int64_t>(k.bond)},
                          {"a", scriptId(k.a)},
                          {"b", scriptId(k.b)},
                          {"mode", k.mode},
                          {"time", k.time},
                          {"step", static_cast<std::int64_t>(k.step)},
                          {"point", vecValue(k.point, s.dim())},
                          {"energy", k.energy},
                          {"measure", k.measure}});
    }
    return Value(std::move(l));
  });

  Command& rm = r.add("bond remove", "Removes bonds (intact or broken).");
  rm.variadicArg("bond", integer().nonNegative(), "bond ids");
  rm.run([](Call& c) {
    std::vector<std::uint32_t> ids;
    for (std::int64_t id : c.all<std::int64_t>("bond"))
      ids.push_back(static_cast<std::uint32_t>(id));
    session(c).scene().removeBonds(ids);
    return Value();
  });
}

}  // namespace demlab::cmd
