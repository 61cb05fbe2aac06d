// Scene options declared once: every option of a module (the integrator, rotation, detection,
// the watchdog, touch) and every sub-model choice of the contact law is one row of the option
// table (sim/option_table.cpp), from which the commands (`module NAME`, `module set|get`,
// `law model`), their help and errors, the Simulation's one get/set pair and the checkpoint
// record follow. Adding an option is one row there and nothing else.
//
// This header is the dimension-free half that the command layer and the public API see: the
// declarations and the checks. The scene fields each row reads and writes live in the
// templated half (sim/option_table.hpp).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace demlab::sim {

// The automatic time step's default accuracy target: a contact lasts at least this many steps
// (SimulationManager::autoStep; `sim timestep auto -stepspercontact`).
inline constexpr double kDefaultStepsPerContact = 20;

// An option's value: a boolean, a real, or one of its choices (by name).
using OptionValue = std::variant<bool, double, std::string>;

enum class OptionType : uint8_t { Boolean, Real, Choice };

// How an option is kept in a checkpoint. The options that existed before the table keep the
// bytes they had, so every existing checkpoint loads and every existing scene's digest stays:
enum class OptionStore : uint8_t {
  Header,   // a fixed slot of the scene's header, in table order (u8 or f64)
  Tagged,   // its group's tagged record after the ledger (OptionGroup::tag), in table order,
            // written only when an option of the group differs from its default
  Section,  // the length-carrying options section, by name, only when not the default
};

// What setting an option invalidates (SimulationManager::setOptions).
enum class OptionEffect : uint8_t {
  Loop,    // the loop is rebuilt, the forces of the last step stay (the trajectory never notices)
  Config,  // the pairs are mixed again and the forces recomputed before the next step
  Search,  // as Config, and a new neighbour search
};

// One option. Reals are finite and within [lo, hi] (open ends where said).
struct OptionSpec {
  std::string_view group;  // the group it belongs to: `module GROUP`, or "law"
  std::string_view name;   // -name in the commands; VALUE <NAME> in errors
  OptionType type;
  OptionValue def;  // the default
  std::string_view help;
  std::span<const std::string_view> choices = {};  // Choice: the accepted words
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loOpen = false, hiOpen = false;
  std::string_view unit = {};  // SI unit shown in help
  OptionStore store = OptionStore::Section;
  OptionEffect effect = OptionEffect::Config;
};

// A group of options: one module's (or the law's sub-model choices).
struct OptionGroup {
  std::string_view name;     // "watchdog"
  std::string_view summary;  // the command's one line
  std::string_view details;  // more help (may be empty)
  // The command is `module NAME ?value?` (one option, given positionally) rather than
  // `module NAME ?-option value ...?`, as the integrator, rotation and touch always were.
  bool positional = false;
  bool isModule = true;  // under `module`; false for the law's sub-models (`law model`)
  const char* tag = "";  // Tagged store: the record's 4-character tag
};

// Returns every option, in table order. Changes nothing.
std::span<const OptionSpec> optionSpecs();
// Returns every group, in table order. Changes nothing.
std::span<const OptionGroup> optionGroups();
// Returns the group named name. Throws {LOOKUP MODULE}: `no module "x" with options: must be
// detection, integrator, ...`.
const OptionGroup& findOptionGroup(std::string_view name);
// Returns the options of group in table order. Changes nothing.
std::vector<const OptionSpec*> groupOptions(std::string_view group);
// Returns the option name of group, its index in optionSpecs() in second. Throws {VALUE OPTION}:
// `bad option "-x": must be -a, -b, or -c` (the command layer's wording).
std::pair<const OptionSpec*, size_t> findOption(std::string_view group, std::string_view name);
// Returns v checked against o and converted to its type (a real given for a boolean: 0 is
// false; a choice by its exact name). Throws {VALUE <NAME>} in the command layer's wording
// (`bad skin "inf": must be a finite number`); changes nothing.
OptionValue checkOption(const OptionSpec& o, const OptionValue& v);
// Returns v as Tcl prints it ("1", "0.5", "verlet").
std::string formatOption(const OptionValue& v);
// Returns what o's reals must be, in words ("a non-negative number"), "" for other types.
std::string optionRange(const OptionSpec& o);

// One option to set: group, name, value (Simulation::setOptions).
struct OptionSetting {
  std::string group, name;
  OptionValue value;
};

}  // namespace demlab::sim
