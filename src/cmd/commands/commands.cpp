#include "cmd/commands/commands.hpp"

#include "cmd/words.hpp"
#include "core/tag_table.hpp"

namespace demlab::cmd {

Registry& registerAllCommands(Registry& r) {
  using Group = void (*)(Registry&);
  static constexpr Group groups[] = {
      registerSimCommands,      registerRunCommands,      registerMaterialCommands,
      registerElementCommands,  registerPackCommands,     registerWallCommands,
      registerBehaviorCommands, registerBondCommands,     registerModuleCommands,
      registerQueryCommands,    registerHelpCommands,     registerSnapshotCommands,
      registerDumpCommands,     registerSeriesCommands,   registerStudyCommands,
      registerAnalysisCommands, registerBoundaryCommands, registerViewerCommands,
      registerPeriodicCommands,
  };
  for (Group g : groups) g(r);
  return r;
}

Value pickFields(const Call& c, const Dict& d) {
  if (c.flagOrder().empty()) return Value(d);
  Dict picked;
  for (const std::string& f : c.flagOrder())
    for (auto& kv : d)
      if (kv.first == f) picked.push_back(kv);
  return picked.size() == 1 ? picked[0].second : Value(picked);
}

std::string materialOrFirst(const Call& c, const sim::Simulation& s) {
  if (c.given("material")) return c.str("material");
  auto names = s.materialNames();
  if (names.empty())
    throw Error("no material defined: use \"material add\" first", {"LOOKUP", "MATERIAL"});
  return names.front();
}

std::vector<std::string> tagsOption(const Call& c) {
  std::vector<std::string> tags;
  if (!c.has("tags")) return tags;
  for (auto& t : splitList(c.str("tags"))) {
    checkTagName(t);
    tags.push_back(t);
  }
  return tags;
}

const Registry& commandRegistry() {
  // Commands such as help hold a reference to the registry, so it is built in place.
  static Registry r;
  static const bool built = (registerAllCommands(r), true);
  (void)built;
  return r;
}

}  // namespace demlab::cmd
