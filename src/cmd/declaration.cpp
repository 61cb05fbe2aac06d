// The declarations as data: what `help -declarations` and `demlab --declarations` return, so
// that tests and the command fuzzer build their calls from the same table as help, completion
// and doc/commands.md, and follow every command and option added later without being edited.
#include <cmath>

#include "cmd/registry.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

const char* kindName(PipeType::Kind k) {
  switch (k) {
    case PipeType::Kind::Real: return "real";
    case PipeType::Kind::Int: return "integer";
    case PipeType::Kind::Bool: return "boolean";
    case PipeType::Kind::Text: return "text";
    case PipeType::Kind::Name: return "name";
    case PipeType::Kind::Choice: return "choice";
    case PipeType::Kind::Vector: return "vector";
    case PipeType::Kind::Reals: return "reals";
    case PipeType::Kind::Ints: return "integers";
    case PipeType::Kind::Custom: return "custom";
  }
  return "custom";
}

// Returns a bound as a number, or "" when there is none.
Value bound(const std::optional<double>& b) {
  return b ? Value(*b) : Value("");
}

std::string role(const Param& p) {
  if (p.positional) return p.variadic ? "variadic" : "positional";
  return p.flag ? "flag" : "option";
}

}  // namespace

Value Command::declaration() const {
  List ps;
  for (const Param& p : params) {
    const PipeType& t = p.type;
    List choices(t.choices.begin(), t.choices.end());
    ps.emplace_back(Dict{{"name", p.name},
                         {"role", role(p)},
                         {"required", p.required},
                         {"optional", p.optional},
                         {"kind", kindName(t.kind)},
                         {"label", t.label},
                         {"unit", t.unit},
                         {"min", bound(t.lo)},
                         {"minopen", t.loOpen},
                         {"max", bound(t.hi)},
                         {"maxopen", t.hiOpen},
                         {"length", t.length},
                         {"choices", Value(choices)},
                         {"default", p.hasDefault ? Value(p.def) : Value("")},
                         {"hasdefault", p.hasDefault}});
  }
  List groups;
  for (const Group& g : exclusive) {
    groups.emplace_back(Dict{{"names", Value(List(g.names.begin(), g.names.end()))},
                             {"requireone", g.requireOne}});
  }
  return Dict{{"command", fullName()},
              {"needsscene", needsScene},
              {"changesscene", changesScene},
              {"needsidle", needsIdle},
              {"onranks", onRanks == OnRanks::Refused  ? "refused"
                          : onRanks == OnRanks::Alike ? "alike"
                                                      : "collective"},
              {"params", Value(ps)},
              {"exclusive", Value(groups)}};
}

Value Registry::declarations(const std::vector<std::string>& topic) const {
  const Node* n = &root_;
  std::string where;
  for (const std::string& w : topic) {
    if (n->command) {
      throw Error("no declarations for \"" + w + "\": " + n->command->fullName() +
                      " has no subcommands",
                  {"LOOKUP", "COMMAND"});
    }
    auto [word, next] = child(*n, w, where);
    where = where.empty() ? word : where + " " + word;
    n = next;
  }
  List out;
  std::vector<const Node*> stack{n};
  while (!stack.empty()) {
    const Node* m = stack.back();
    stack.pop_back();
    if (m->command) out.push_back(m->command->declaration());
    for (auto it = m->children.rbegin(); it != m->children.rend(); ++it)
      stack.push_back(it->second.get());
  }
  return out;
}

}  // namespace demlab::cmd
