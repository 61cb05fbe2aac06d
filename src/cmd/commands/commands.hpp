// The command groups, one file each, and the one table that registers them all.
#pragma once

#include "cmd/registry.hpp"
#include "cmd/session.hpp"

namespace demlab::cmd {

void registerSimCommands(Registry& r);  // sim: new, info, timestep, digest, save, load, keep...
void registerRunCommands(Registry& r);  // sim run, sim step
void registerMaterialCommands(Registry& r);  // material, law
void registerElementCommands(Registry& r);   // element
void registerPackCommands(Registry& r);      // pack: lattice, random, file
void registerWallCommands(Registry& r);      // wall
void registerBehaviorCommands(Registry& r);  // behavior
void registerModuleCommands(Registry& r);    // module: list, integrator, rotation, detection
void registerQueryCommands(Registry& r);     // energy, contacts, bounds, counts
void registerHelpCommands(Registry& r);      // help
void registerSnapshotCommands(Registry& r);  // snapshot: write, every, list, off, read
void registerStudyCommands(Registry& r);     // study: convergence

// Declares "<group> tag" and "<group> untag" for the objects ref names (element or wall ids
// or names, as Id): each calls tag or untag of the scene for every object given, so the tag
// rules (TagTable) are the scene's. Changes r.
template <class Id>
void addTagCommands(Registry& r, const std::string& group, const std::string& objects, PipeType ref,
                    void (sim::Simulation::*tag)(Id, const std::string&),
                    void (sim::Simulation::*untag)(Id, const std::string&)) {
  const std::string what = group + " ids or names";
  Command& add = r.add(group + " tag", "Gives " + objects + " a tag (idempotent).");
  add.arg("tag", tagName(), "the tag");
  add.variadicArg(group, ref, what);
  add.run([group, tag](Call& c) {
    auto& s = session(c).scene();
    for (Id id : c.all<Id>(group)) (s.*tag)(id, c.str("tag"));
    return Value();
  });
  Command& remove = r.add(group + " untag", "Takes a tag away from " + objects + ".");
  remove.arg("tag", tagName(), "the tag");
  remove.variadicArg(group, ref, what);
  remove.run([group, untag](Call& c) {
    auto& s = session(c).scene();
    for (Id id : c.all<Id>(group)) (s.*untag)(id, c.str("tag"));
    return Value();
  });
}

// Registers every command group (the table: one row per group). Returns r.
Registry& registerAllCommands(Registry& r);

// Returns the process-wide registry with every command declared (built on first use).
const Registry& commandRegistry();

}  // namespace demlab::cmd
