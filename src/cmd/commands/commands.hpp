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

// Registers every command group (the table: one row per group). Returns r.
Registry& registerAllCommands(Registry& r);

// Returns the process-wide registry with every command declared (built on first use).
const Registry& commandRegistry();

}  // namespace demlab::cmd
