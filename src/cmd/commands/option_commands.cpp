// Commands built from the option table (option_commands.hpp).
#include "cmd/commands/option_commands.hpp"

#include <cmath>

namespace demlab::cmd {

PipeType optionPipe(const sim::OptionSpec& o) {
  switch (o.type) {
    case sim::OptionType::Boolean:
      return boolean();
    case sim::OptionType::Choice:
      return choice(std::vector<std::string>(o.choices.begin(), o.choices.end()));
    case sim::OptionType::Real:
      break;
  }
  PipeType t = real();
  if (std::isfinite(o.lo)) t = t.min(o.lo, o.loOpen);
  if (std::isfinite(o.hi)) t = t.max(o.hi, o.hiOpen);
  if (!o.unit.empty()) t = t.withUnit(std::string(o.unit));
  return t;
}

Value optionValue(const sim::OptionValue& v) {
  if (const bool* b = std::get_if<bool>(&v)) return Value(*b);
  if (const double* x = std::get_if<double>(&v)) return Value(*x);
  return Value(std::get<std::string>(v));
}

Value optionDict(const sim::Simulation& s, std::string_view group) {
  Dict d;
  for (const sim::OptionSpec* o : sim::groupOptions(group)) {
    d.emplace_back(std::string(o->name), optionValue(s.option(group, o->name)));
  }
  return Value(d);
}

void addOptionParams(Command& cmd, std::string_view group) {
  const bool positional = sim::findOptionGroup(group).positional;
  for (const sim::OptionSpec* o : sim::groupOptions(group)) {
    const std::string name(o->name), help(o->help);
    if (positional) {
      cmd.optionalArg(name, optionPipe(*o), help);
    } else {
      cmd.option(name, optionPipe(*o), help);
    }
  }
}

std::vector<sim::OptionSetting> givenOptions(const Call& c, std::string_view group) {
  std::vector<sim::OptionSetting> out;
  for (const sim::OptionSpec* o : sim::groupOptions(group)) {
    if (!c.given(o->name)) continue;
    sim::OptionValue v;
    switch (o->type) {
      case sim::OptionType::Boolean:
        v = c.get<bool>(o->name);
        break;
      case sim::OptionType::Real:
        v = c.real(o->name);
        break;
      case sim::OptionType::Choice:
        v = c.str(o->name);
        break;
    }
    out.push_back({std::string(group), std::string(o->name), v});
  }
  return out;
}

}  // namespace demlab::cmd
