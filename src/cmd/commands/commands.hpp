// The command groups, one file each, and the one table that registers them all.
#pragma once

#include <cctype>
#include <cstdint>
#include <string>
#include <utility>

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
void registerBondCommands(Registry& r);      // bond: model, add, file, list, query, breaks
void registerModuleCommands(Registry& r);    // module: list, integrator, rotation, detection
void registerQueryCommands(Registry& r);     // energy, contacts, bounds, counts
void registerHelpCommands(Registry& r);      // help
void registerSnapshotCommands(Registry& r);
void registerDumpCommands(Registry& r);      // dump: vtk, every, list, off, csv, lammps
void registerSeriesCommands(Registry& r);    // series: every, get, list, off, plot
void registerStudyCommands(Registry& r);     // study: convergence
void registerAnalysisCommands(Registry& r);  // query stress, coordination, fabric, packing...
void registerBoundaryCommands(Registry& r);  // inlet (sources), sink
void registerViewerCommands(Registry& r);    // viewer: open, close, selection, frame, pick...
void registerPeriodicCommands(Registry& r);  // periodic: set, get, clear

// Returns the pipe of a region argument, `{box {lo} {hi}}`, `{sphere {centre} radius}` (a
// disc in 2D) or `{cylinder {centre} {axis} radius halflength}` (3D), giving a sim::Region; a bad
// word is {VALUE REGION} (pack.cpp).
PipeType regionType();
// Returns the pipe of a size distribution of radii: a number, {uniform a b}, {normal mean sd}
// (truncated at 3 sd), {powerlaw a b exponent} or {discrete r1 w1 r2 w2 ...}, giving a
// sim::SizeDistribution; a bad word is {VALUE RADIUS} (pack.cpp).
PipeType sizeType();

// Returns the dict d itself when the call gave no field flags, else the fields the flags name,
// in the flags' order: the value alone for one flag, a dict of them for several. Changes nothing.
Value pickFields(const Call& c, const Dict& d);

// Returns the material the call's -material option names, or the scene's first material.
// Throws {LOOKUP MATERIAL} when the scene has none.
std::string materialOrFirst(const Call& c, const sim::Simulation& s);

// Returns the tags of the call's -tags option (none when not given), each checked ({VALUE TAG}).
std::vector<std::string> tagsOption(const Call& c);

// Rethrows e, or, when it is a lookup of a handle, the pipe's error for a missing id of that
// kind ("no element with id 7", LOOKUP ELEMENT): a distributed scene's owner checks an element
// id in the command, not in the pipe, and answers alike.
[[noreturn]] inline void rethrowLookup(const Error& e, const std::string& kind, std::int64_t id) {
  if (e.code().size() < 3 || e.code()[2] != "HANDLE") throw e;
  std::string code = kind;
  for (char& ch : code) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  throw Error("no " + kind + " with id " + std::to_string(id), {"LOOKUP", code});
}

// Declares "<group> tag" and "<group> untag" for the objects ref names (element or wall ids
// or names, as Id): each calls tag or untag of the scene for every object given, so the tag
// rules (TagTable) are the scene's; onRanks says how a distributed scene runs them. Changes r.
template <class Id>
void addTagCommands(Registry& r, const std::string& group, const std::string& objects, PipeType ref,
                    void (sim::Simulation::*tag)(Id, const std::string&),
                    void (sim::Simulation::*untag)(Id, const std::string&), OnRanks onRanks) {
  using Change = void (sim::Simulation::*)(Id, const std::string&);
  const std::pair<std::string, Change> verbs[] = {{" tag", tag}, {" untag", untag}};
  for (const auto& [verb, change] : verbs) {
    Command& cmd = r.add(group + verb, change == tag ? "Gives " + objects + " a tag (idempotent)."
                                                     : "Takes a tag away from " + objects + ".");
    cmd.arg("tag", tagName(), "the tag");
    cmd.variadicArg(group, ref, group + " ids or names");
    cmd.onRanks = onRanks;
    cmd.run([group, change](Call& c) {
      auto& s = session(c).scene();
      for (Id id : c.all<Id>(group)) {
        try {
          (s.*change)(id, c.str("tag"));
        } catch (const Error& e) {
          rethrowLookup(e, group, id.scriptId());
        }
      }
      return Value();
    });
  }
}

// Registers every command group (the table: one row per group). Returns r.
Registry& registerAllCommands(Registry& r);

// Returns the process-wide registry with every command declared (built on first use).
const Registry& commandRegistry();

}  // namespace demlab::cmd
