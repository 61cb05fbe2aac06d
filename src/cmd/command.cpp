#include "cmd/command.hpp"

#include <algorithm>

#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

bool looksLikeOption(std::string_view w) {
  if (w.size() < 2 || w[0] != '-') return false;
  double d;
  return !readReal(w, d);  // "-1.5" is a number, not an option
}

}  // namespace

std::string Param::usage() const {
  std::string placeholder = name;
  if (positional) {
    if (variadic) return optional ? "?" + name + " ...?" : name + " ?" + name + " ...?";
    if (optional) return "?" + name + "?";
    return name;
  }
  if (flag) return "-" + name;
  return "-" + name + " " + placeholder;
}

Param& Command::arg(std::string n, PipeType t, std::string h) {
  Param p;
  p.name = std::move(n);
  p.type = std::move(t);
  p.help = std::move(h);
  p.positional = true;
  p.required = true;
  params.push_back(std::move(p));
  return params.back();
}

Param& Command::optionalArg(std::string n, PipeType t, std::string h) {
  Param& p = arg(std::move(n), std::move(t), std::move(h));
  p.required = false;
  p.optional = true;
  return p;
}

Param& Command::variadicArg(std::string n, PipeType t, std::string h) {
  Param& p = arg(std::move(n), std::move(t), std::move(h));
  p.variadic = true;
  return p;
}

Param& Command::option(std::string n, PipeType t, std::string h) {
  Param p;
  p.name = std::move(n);
  p.type = std::move(t);
  p.help = std::move(h);
  params.push_back(std::move(p));
  return params.back();
}

Param& Command::flag(std::string n, std::string h) {
  Param& p = option(std::move(n), boolean(), std::move(h));
  p.flag = true;
  return p;
}

Command& Command::oneOf(std::vector<std::string> names, bool requireOne) {
  exclusive.push_back({std::move(names), requireOne});
  return *this;
}

std::string Command::fullName() const {
  std::string s;
  for (const std::string& w : path) {
    if (!s.empty()) s += ' ';
    s += w;
  }
  return s;
}

std::string Command::usage() const {
  std::string s = fullName();
  bool hasOptional = false;
  for (const Param& p : params) {
    if (p.positional || p.required) {
      s += ' ';
      s += p.usage();
    } else {
      hasOptional = true;
    }
  }
  for (const Group& g : exclusive) {
    if (!g.requireOne) continue;
    std::string alt;
    for (const std::string& n : g.names) {
      if (!alt.empty()) alt += " | ";
      alt += find(n)->usage();
    }
    s += ' ';
    s += alt;
  }
  if (hasOptional) s += " ?-option value ...?";
  return s;
}

const Param* Command::find(std::string_view n) const {
  for (const Param& p : params)
    if (p.name == n) return &p;
  return nullptr;
}

std::vector<std::string> Command::optionNames() const {
  std::vector<std::string> out;
  for (const Param& p : params)
    if (!p.positional) out.push_back("-" + p.name);
  return out;
}

std::string Command::helpText() const {
  const std::size_t width = helpWidth();
  std::string s = usage() + "\n" + wrapText(summary, width, 4, 4);
  if (!details.empty()) s += "\n" + wrapText(details, width, 4, 4);
  std::vector<std::pair<std::string, std::string>> rows;
  for (const Param& p : params) {
    std::string left = p.positional ? p.name : "-" + p.name;
    if (!p.positional && !p.flag) left += " " + p.type.label;
    std::string right = p.help;
    std::string unit = p.type.unit, range = p.type.constraint();
    if (!unit.empty()) right += " [" + unit + "]";
    if (!range.empty()) right += " (" + range + ")";
    if (p.type.kind == PipeType::Kind::Choice) right += ": " + alternatives(p.type.choices);
    if (p.required && !p.positional) right += "; required";
    if (p.hasDefault) right += "; default " + quoteElement(p.def);
    rows.emplace_back(left, right);
  }
  for (const Group& g : exclusive) {
    std::vector<std::string> names;
    for (const std::string& n : g.names) names.push_back("-" + n);
    rows.emplace_back("",
                      (g.requireOne ? "exactly one of " : "at most one of ") + alternatives(names));
  }
  if (!rows.empty()) {
    std::size_t w = 0;
    for (auto& r : rows) w = std::max(w, r.first.size());
    s += "\n";
    for (auto& [l, r] : rows) s += helpRow(l, w, r, width);
  }
  return s;
}

std::string Command::markdown() const {
  std::string s = "### `" + usage() + "`\n\n" + summary + "\n\n";
  if (!details.empty()) s += details + "\n\n";
  if (onRanks == OnRanks::Alike) {
    s += "Distributed runs: acts alike on every rank.\n\n";
  } else if (onRanks == OnRanks::Collective) {
    s += "Distributed runs: collective, every rank gets the whole scene's answer.\n\n";
  }
  if (!params.empty()) {
    s += "| argument | type | unit | range | default | description |\n|---|---|---|---|---|---|\n";
    auto cell = [](std::string x) {
      std::string out;
      for (char c : x) {
        if (c == '|')
          out += "\\|";
        else
          out += c;
      }
      return out;
    };
    for (const Param& p : params) {
      std::string n = p.positional ? p.name : "-" + p.name;
      std::string type = p.flag ? "flag" : p.type.label;
      std::string desc = p.help;
      if (p.required && !p.positional) desc += " (required)";
      if (p.variadic) desc += " (one or more)";
      if (p.optional) desc += " (optional)";
      std::string def;
      if (p.hasDefault) def = '`' + cell(p.def) + '`';
      s += "| `" + n + "` | " + cell(type) + " | " + cell(p.type.unit) + " | " +
           cell(p.type.constraint()) + " | " + def + " | " + cell(desc) + " |\n";
    }
    for (const Group& g : exclusive) {
      std::vector<std::string> names;
      for (const std::string& n : g.names) names.push_back("`-" + n + "`");
      s += "\n" + std::string(g.requireOne ? "Exactly one of " : "At most one of ") +
           alternatives(names) + ".\n";
    }
    s += "\n";
  }
  return s;
}

ArgStack::ArgStack(const Command& c) {
  slots_.reserve(c.params.size());
  for (const Param& p : c.params) slots_.push_back(Slot{&p, {}, false, {}});
}

Slot& ArgStack::slot(std::string_view n) {
  for (Slot& s : slots_)
    if (s.param->name == n) return s;
  throw Error("internal error: no parameter \"" + std::string(n) + "\"", {"INTERNAL"});
}

const Slot& ArgStack::slot(std::string_view n) const {
  return const_cast<ArgStack*>(this)->slot(n);
}

const Param& CommandLine::matchOption(const Command& c, std::string_view word) {
  const Param* hit = nullptr;
  int prefixHits = 0;
  std::string_view body = word.substr(1);
  for (const Param& p : c.params) {
    if (p.positional) continue;
    if (p.name == body) return p;
    if (!body.empty() && p.name.compare(0, body.size(), body) == 0) {
      hit = &p;
      ++prefixHits;
    }
  }
  if (prefixHits == 1 && word.size() > 1) return *hit;
  std::vector<std::string> names = c.optionNames();
  if (names.empty()) {
    throw Error("bad option \"" + std::string(word) + "\": " + c.fullName() + " takes no options",
                {"OPTION"});
  }
  throw Error(std::string(prefixHits > 1 ? "ambiguous" : "bad") + " option \"" + std::string(word) +
                  "\": must be " + alternatives(names),
              {"OPTION"});
}

bool CommandLine::parse(ArgStack& stack) const {
  const std::vector<std::string>& w = words_;
  auto wrongArgs = [&]() -> Error {
    return Error("wrong # args: should be \"" + cmd_.usage() + "\"", {"ARGS"});
  };
  std::size_t i = 0;
  for (Slot& s : stack.slots()) {
    const Param& p = *s.param;
    if (!p.positional) continue;
    if (i < w.size() && w[i] == "-help" && !cmd_.find("help")) return false;
    if (p.variadic) {
      while (i < w.size() && !looksLikeOption(w[i])) s.words.push_back(w[i++]);
      if (s.words.empty() && !p.optional) throw wrongArgs();
      s.given = !s.words.empty();
    } else if (p.optional) {
      if (i < w.size() && !looksLikeOption(w[i])) {
        s.words.push_back(w[i++]);
        s.given = true;
      }
    } else {
      if (i >= w.size()) throw wrongArgs();
      s.words.push_back(w[i++]);
      s.given = true;
    }
  }
  bool hasOptions = !cmd_.optionNames().empty();
  while (i < w.size()) {
    const std::string& word = w[i];
    if (word == "-help" && !cmd_.find("help")) return false;
    if (!hasOptions) throw wrongArgs();
    if (word.size() < 2 || word[0] != '-') {
      // A stray word where an option should be: Tcl reports it as a bad option.
      throw Error("bad option \"" + word + "\": must be " + alternatives(cmd_.optionNames()),
                  {"OPTION"});
    }
    const Param& p = matchOption(cmd_, word);
    Slot& s = stack.slot(p.name);
    if (p.flag) {
      s.words = {"1"};
      s.given = true;
      auto& order = stack.flagOrder();
      if (std::find(order.begin(), order.end(), p.name) == order.end()) order.push_back(p.name);
      ++i;
      continue;
    }
    if (i + 1 >= w.size()) {
      throw Error("value for \"" + word + "\" missing", {"ARGS"});
    }
    s.words = {w[i + 1]};  // the last of repeated options wins, as in Tcl
    s.given = true;
    i += 2;
  }
  for (const Slot& s : stack.slots()) {
    if (!s.param->positional && s.param->required && !s.given) {
      throw Error(
          "missing required option -" + s.param->name + ": should be \"" + cmd_.usage() + "\"",
          {"ARGS"});
    }
  }
  for (const Command::Group& g : cmd_.exclusive) {
    std::vector<std::string> given, all;
    for (const std::string& n : g.names) {
      all.push_back("-" + n);
      if (stack.slot(n).given) given.push_back("-" + n);
    }
    if (given.size() > 1) {
      throw Error("conflicting options " + alternatives(given, "and") + ": give at most one of " +
                      alternatives(all),
                  {"ARGS"});
    }
    if (g.requireOne && given.empty()) {
      throw Error("wrong # args: should be \"" + cmd_.usage() + "\"", {"ARGS"});
    }
  }
  return true;
}

void PipeLine::check(const Command& c, ArgStack& stack, const Context& ctx) {
  for (Slot& s : stack.slots()) {
    const Param& p = *s.param;
    if (s.given) {
      if (p.flag) {
        s.value = true;
      } else if (p.variadic) {
        std::vector<std::any> vals;
        for (const std::string& w : s.words) vals.push_back(convertWord(w, p, ctx));
        s.value = std::move(vals);
      } else {
        s.value = convertWord(s.words[0], p, ctx);
      }
    } else if (p.hasDefault) {
      s.value = convertWord(p.def, p, ctx);
    } else if (p.flag) {
      s.value = false;
    }
  }
  (void)c;
}

void PipeLine::fill(const ArgStack& stack, void* def, const std::type_info& type) {
  for (const Slot& s : stack.slots()) {
    const Param& p = *s.param;
    if (p.dest && p.destType && *p.destType == type && s.value.has_value()) p.dest(def, s.value);
  }
}

void Call::bad(std::string_view param, std::string_view why) const {
  const Slot& s = stack_.slot(param);
  std::string word = s.words.empty() ? s.param->def : s.words[0];
  throw Error("bad " + std::string(param) + " \"" + word + "\": " + std::string(why),
              {"VALUE", codeWord(param)});
}

}  // namespace demlab::cmd
