#include "cmd/commands/commands.hpp"

namespace demlab::cmd {

Registry& registerAllCommands(Registry& r) {
  using Group = void (*)(Registry&);
  static constexpr Group groups[] = {
      registerSimCommands,      registerRunCommands,    registerMaterialCommands,
      registerElementCommands,  registerPackCommands,   registerWallCommands,
      registerBehaviorCommands, registerModuleCommands, registerQueryCommands,
      registerHelpCommands,     registerSnapshotCommands,
      registerDumpCommands,     registerSeriesCommands,
      registerStudyCommands,    registerAnalysisCommands, registerBoundaryCommands,
  };
  for (Group g : groups) g(r);
  return r;
}

const Registry& commandRegistry() {
  // Commands such as help hold a reference to the registry, so it is built in place.
  static Registry r;
  static const bool built = (registerAllCommands(r), true);
  (void)built;
  return r;
}

}  // namespace demlab::cmd
