// Queries of the whole scene: the energy ledger, contacts, bounds, counts.
#include <tuple>

#include "cmd/commands/commands.hpp"
#include "mpi/records.hpp"
#include "core/free_aside.hpp"
#include "core/interrupt.hpp"

namespace demlab::cmd {

namespace {

// Returns every rank's contacts (each computed on one rank), by the ids of their ends, on every
// rank. Collective.
std::vector<sim::ContactInfo> gatheredContacts(const sim::Simulation& s,
                                               const std::vector<sim::ContactInfo>& mine) {
  std::vector<sim::ContactInfo> all = mpi::gatherRecords(ranksOf(s), mine);
  const auto key = [](const sim::ContactInfo& k) {
    return std::make_tuple(k.a.scriptId(), k.b.isNull() ? -1 : k.b.scriptId(),
                           k.wall.isNull() ? -1 : k.wall.scriptId());
  };
  std::stable_sort(all.begin(), all.end(),
                   [&](const auto& x, const auto& y) { return key(x) < key(y); });
  return all;
}

}  // namespace

void registerQueryCommands(Registry& r) {
  r.describe("query",
             "Questions about the scene: energy, contacts, bounds, counts; and the micromechanics "
             "of a region or tag group: stress, coordination, fabric, packing, motion, cg.");

  Command& en =
      r.add("query energy", "Returns the energy ledger as a dict (J), or one entry of it.");
  en.onRanks = OnRanks::Collective;
  en.details =
      "balance = kinetic + gravitational + elastic + losses - work done on the grains, relative to "
      "the "
      "scene's first step; residual = |balance| / scale is the run's error indicator.";
  static const char* const fields[] = {"kinetic", "rotational", "gravitational", "elastic",
                                       "damping", "friction",   "wallwork",      "behaviorwork",
                                       "balance", "scale",      "residual"};
  for (const char* f : fields) en.flag(f, std::string("the ") + f + " entry alone");
  en.changesScene = false;
  en.run([](Call& c) {
    sim::EnergyLedger e = session(c).scene().energy();
    Dict d{{"kinetic", e.kineticTranslational},
           {"rotational", e.kineticRotational},
           {"gravitational", e.gravitational},
           {"elastic", e.elastic},
           {"damping", e.dampingLoss},
           {"friction", e.frictionLoss},
           {"wallwork", e.wallWork},
           {"behaviorwork", e.behaviorWork},
           {"balance", e.balance},
           {"scale", e.scale},
           {"residual", e.residual}};
    return pickFields(c, d);
  });

  Command& ct = r.add("query contacts",
                      "Returns the contacts of the last step as a list of dicts, or their number.");
  ct.details =
      "Each dict: a (element id), b (element id or empty), wall (wall id or empty), point, normal, "
      "overlap, force (on b). A distributed run's, gathered from every rank, by a, b and wall.";
  ct.flag("count", "return the number of contacts only");
  ct.option("element", elementRef(), "only the contacts of this element (as a or b)");
  ct.changesScene = false;
  ct.onRanks = OnRanks::Collective;
  ct.run([](Call& c) {
    auto& s = session(c).scene();
    const bool one = c.given("element");
    if (c.flag("count") && !one) return Value(ranksOf(s).sum(std::int64_t(s.contactCount())));
    const sim::ElementId e = one ? c.get<sim::ElementId>("element") : sim::ElementId{};
    int d = s.dim();
    if (one && s.distributed() && ranksOf(s).sum(std::int64_t(!s.ownedElement(e).isNull())) == 0) {
      throw Error("no element with id " + std::to_string(scriptId(e)), {"LOOKUP", "ELEMENT"});
    }
    std::vector<sim::ContactInfo> contacts = s.contacts();
    if (s.distributed()) contacts = gatheredContacts(s, contacts);
    List l;
    // Stopped, hundreds of thousands of dicts and the contacts are freed on a thread of their own.
    const FreeAsideOnThrow asideContacts(contacts);
    const FreeAsideOnThrow aside(l);
    std::size_t n = 0;
    InterruptPoll poll("query contacts");
    for (const auto& k : contacts) {
      poll();
      if (one && !(k.a == e || k.b == e)) continue;
      ++n;
      if (c.flag("count")) continue;
      l.emplace_back(Dict{{"a", scriptId(k.a)},
                          {"b", k.b.isNull() ? Value("") : Value(scriptId(k.b))},
                          {"wall", k.wall.isNull() ? Value("") : Value(scriptId(k.wall))},
                          {"point", vecValue(k.point, d)},
                          {"normal", vecValue(k.normal, d)},
                          {"overlap", k.overlap},
                          {"force", vecValue(k.force, d)}});
    }
    if (c.flag("count")) return Value(n);
    return Value(std::move(l));
  });

  Command& bb =
      r.add("query bounds", "Returns the box {lo hi} holding every element and finite wall.");
  bb.onRanks = OnRanks::Collective;
  bb.changesScene = false;
  bb.run([](Call& c) {
    auto& s = session(c).scene();
    auto b = s.bounds();
    return Value(List{vecValue(b[0], s.dim()), vecValue(b[1], s.dim())});
  });

  Command& cnt = r.add(
      "query counts", "Returns a dict of counts: elements, walls, contacts, behaviors, materials.");
  cnt.onRanks = OnRanks::Collective;
  cnt.changesScene = false;
  cnt.run([](Call& c) {
    auto& s = session(c).scene();
    // Each rank's own elements (a distributed scene's, not its ghosts) and the contacts it
    // computed, summed.
    std::vector<std::int64_t> sums{std::int64_t(s.distribution().owned),
                                   std::int64_t(s.contactCount())};
    ranksOf(s).sum(sums);
    return Value(Dict{{"elements", sums[0]},
                      {"walls", s.wallCount()},
                      {"contacts", sums[1]},
                      {"behaviors", s.behaviors().size()},
                      {"materials", s.materialNames().size()}});
  });
}

void registerHelpCommands(Registry& r) {
  Command& h =
      r.add("help", "Describes the commands: help, help <command>, help <command> <subcommand>.");
  h.onRanks = OnRanks::Alike;
  h.variadicArg("topic", text("word"), "a command and subcommand (unique prefixes accepted)")
      .optional = true;
  h.flag("declarations",
         "return the declarations of the commands under the topic as data: a list of dicts "
         "(command, params with their kind, range, unit, default...), for tests and tools");
  h.needsScene = false;
  h.changesScene = false;
  h.run([&r](Call& c) {
    std::vector<std::string> topic;
    if (c.given("topic")) topic = c.all<std::string>("topic");
    if (c.flag("declarations")) return r.declarations(topic);
    return Value(r.help(topic));
  });
}

}  // namespace demlab::cmd
