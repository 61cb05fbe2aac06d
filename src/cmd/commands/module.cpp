// The "module" group: the stages of the time step a scene runs, and their options. Every
// option command is built from the option table (sim/options.hpp): `module NAME` for each
// module with options, and the generic `module set` / `module get`.
#include <algorithm>
#include <limits>
#include <map>

#include "cmd/commands/commands.hpp"
#include "cmd/commands/option_commands.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

// Returns the names of the groups under `module`, in table order.
std::vector<std::string> moduleGroups() {
  std::vector<std::string> out;
  for (const sim::OptionGroup& g : sim::optionGroups()) {
    if (g.isModule) out.emplace_back(g.name);
  }
  return out;
}

// Declares `module NAME` for group g: its options as parameters; it sets those given and
// returns the option's value (a positional group) or the group's dict.
void addGroupCommand(Registry& r, const sim::OptionGroup& g) {
  const std::string group(g.name);
  Command& cmd = r.add("module " + group, std::string(g.summary));
  cmd.details = std::string(g.details);
  addOptionParams(cmd, group);
  cmd.run([group, positional = g.positional](Call& c) {
    auto& s = session(c).scene();
    const auto given = givenOptions(c, group);
    if (!given.empty()) s.setOptions(given);
    if (positional) return optionValue(s.option(group, sim::groupOptions(group)[0]->name));
    return optionDict(s, group);
  });
}

// Declares `module set`: every module option once (an option name two modules share has one
// type), each call taking those of the module named.
void addSetCommand(Registry& r) {
  Command& set = r.add("module set", "Sets options of a module; returns its options as a dict.");
  set.details = "The options are those of `module NAME` (help module NAME): one of " +
                alternatives(moduleGroups()) + ". Given none, it sets nothing.";
  set.arg("module", choice(moduleGroups()), "the module");
  std::map<std::string, std::pair<const sim::OptionSpec*, std::string>> names;  // name: help
  std::vector<std::string> order;
  for (const std::string& group : moduleGroups()) {
    for (const sim::OptionSpec* o : sim::groupOptions(group)) {
      auto [it, fresh] = names.try_emplace(std::string(o->name), o, "");
      if (fresh) order.emplace_back(o->name);
      if (!fresh && it->second.first->type != o->type) {
        throw Error("internal: module option -" + std::string(o->name) + " has two types",
                    {"INTERNAL"});
      }
      it->second.second += (fresh ? "" : "; ") + group + ": " + std::string(o->help);
    }
  }
  for (const std::string& n : order) {
    const auto& [o, help] = names.at(n);
    PipeType pipe = optionPipe(*o);
    if (o->type == sim::OptionType::Choice) {
      // Matched against the module's own choices in the check phase.
      pipe = text(std::string(pipe.label));
    } else if (help.find("; ") != std::string::npos) {
      // Shared: each module's range is checked by setOptions, in the same words.
      pipe.lo.reset();
      pipe.hi.reset();
    }
    set.option(n, pipe, help);
  }
  // The check phase: each option given must be the module's, a choice is matched as
  // `module NAME` matches it (unique prefixes); the settings go to the execute phase.
  set.onCheck([](Call& c) {
    const std::string group = c.str("module");
    std::vector<sim::OptionSetting> given;
    for (const Slot& slot : c.stack().slots()) {
      if (!slot.given || slot.param->positional) continue;
      const sim::OptionSpec& o = *sim::findOption(group, slot.param->name).first;
      sim::OptionValue v;
      if (auto* b = std::any_cast<bool>(&slot.value)) v = *b;
      if (auto* x = std::any_cast<double>(&slot.value)) v = *x;
      if (auto* w = std::any_cast<std::string>(&slot.value)) {
        v = matchChoice(*w, std::vector<std::string>(o.choices.begin(), o.choices.end()), o.name,
                        {"VALUE", codeWord(o.name)});
      }
      given.push_back({group, slot.param->name, sim::checkOption(o, v)});
    }
    c.prepared = given;
  });
  set.run([](Call& c) {
    auto& s = session(c).scene();
    const auto& given = std::any_cast<const std::vector<sim::OptionSetting>&>(c.prepared);
    if (!given.empty()) s.setOptions(given);
    return optionDict(s, c.str("module"));
  });
}

}  // namespace

void registerModuleCommands(Registry& r) {
  r.describe("module", "The modules of the time step: which run, and their options.");

  Command& list = r.add("module list", "Returns the modules the next step runs, in loop order.");
  list.onRanks = OnRanks::Alike;
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (auto& m : session(c).scene().listModules()) l.emplace_back(m);
    return Value(std::move(l));
  });

  for (const sim::OptionGroup& g : sim::optionGroups()) {
    if (g.isModule) addGroupCommand(r, g);
  }
  addSetCommand(r);

  Command& get = r.add("module get", "Returns a module's options as a dict, or one of them.");
  get.onRanks = OnRanks::Alike;
  get.changesScene = false;
  get.arg("module", choice(moduleGroups()), "the module");
  get.optionalArg("option", text("option"), "an option's name, without the -");
  get.run([](Call& c) {
    const auto& s = session(c).scene();
    const std::string group = c.str("module");
    if (!c.given("option")) return optionDict(s, group);
    return optionValue(s.option(group, sim::findOption(group, c.str("option")).first->name));
  });
}

}  // namespace demlab::cmd
