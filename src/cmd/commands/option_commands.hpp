// Commands built from the option table (sim/options.hpp): a group's options become a
// command's parameters, with the table's types, ranges, choices and help, so the `module`
// commands and `law model` carry no per-option code.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cmd/commands/commands.hpp"
#include "sim/options.hpp"

namespace demlab::cmd {

// Returns the pipe of option o: its kind, range, unit and choices. Changes nothing.
PipeType optionPipe(const sim::OptionSpec& o);
// Returns the Tcl value of an option's value.
Value optionValue(const sim::OptionValue& v);
// Returns the options of group in the scene as a dict, in table order. Changes nothing.
Value optionDict(const sim::Simulation& s, std::string_view group);
// Declares every option of group on cmd as -name options (as a positional when the group is
// positional). Changes cmd.
void addOptionParams(Command& cmd, std::string_view group);
// Returns the settings of group's options given in call c. Changes nothing.
std::vector<sim::OptionSetting> givenOptions(const Call& c, std::string_view group);

}  // namespace demlab::cmd
