#include "cmd/registry.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

std::vector<std::string> splitPath(std::string_view path) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : path) {
    if (c == ' ') {
      if (!cur.empty()) out.push_back(std::move(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

bool startsWith(std::string_view s, std::string_view p) {
  return s.substr(0, p.size()) == p;
}

}  // namespace

Command& Registry::add(std::string_view path, std::string summary) {
  std::vector<std::string> words = splitPath(path);
  Node* n = &root_;
  for (const std::string& w : words) {
    if (n->command)
      throw Error("internal error: command \"" + std::string(path) + "\" under a command",
                  {"INTERNAL"});
    auto& slot = n->children[w];
    if (!slot) slot = std::make_unique<Node>();
    n = slot.get();
  }
  if (n->command || !n->children.empty()) {
    throw Error("internal error: command \"" + std::string(path) + "\" declared twice",
                {"INTERNAL"});
  }
  Command& c = commands_.emplace_back();
  c.path = words;
  c.summary = std::move(summary);
  n->command = &c;
  return c;
}

void Registry::describe(std::string_view group, std::string summary) {
  Node* n = &root_;
  for (const std::string& w : splitPath(group)) {
    auto& slot = n->children[w];
    if (!slot) slot = std::make_unique<Node>();
    n = slot.get();
  }
  n->summary = std::move(summary);
}

void Registry::shorthand(std::string_view group, std::string_view subcommand, std::string suffix) {
  Node* n = &root_;
  for (const std::string& w : splitPath(group)) {
    auto it = n->children.find(w);
    if (it == n->children.end()) throw Error("shorthand for an undeclared group", {"INTERNAL"});
    n = it->second.get();
  }
  if (n->command || !n->children.contains(subcommand) || suffix.empty()) {
    throw Error("shorthand needs a group, one of its subcommands and a suffix", {"INTERNAL"});
  }
  n->shorthandWord = std::string(subcommand);
  n->shorthandSuffix = std::move(suffix);
}

std::vector<std::string> Registry::topWords() const {
  std::vector<std::string> out;
  for (const auto& [w, n] : root_.children) out.push_back(w);
  return out;
}

std::string Registry::shorthandLine(const Node& n, const std::string& where) {
  const std::string arg = "NAME" + n.shorthandSuffix + " ?arg ...?";
  return "`" + where + " " + arg + "` is short for `" + where + " " + n.shorthandWord + " " + arg +
         "`.";
}

bool Registry::takesShorthand(const Node& n, std::string_view word) {
  const std::string& suffix = n.shorthandSuffix;
  if (suffix.empty() || word.size() <= suffix.size() ||
      word.substr(word.size() - suffix.size()) != suffix) {
    return false;
  }
  for (const auto& [w, c] : n.children) {
    if (startsWith(w, word)) return false;
  }
  return true;
}

std::pair<std::string, const Registry::Node*> Registry::child(const Node& n, std::string_view word,
                                                              const std::string& where) const {
  if (auto it = n.children.find(word); it != n.children.end()) return {it->first, it->second.get()};
  const Node* hit = nullptr;
  std::string hitWord;
  int hits = 0;
  std::vector<std::string> names;
  for (const auto& [w, c] : n.children) {
    names.push_back(w);
    if (!word.empty() && startsWith(w, word)) {
      hit = c.get();
      hitWord = w;
      ++hits;
    }
  }
  if (hits == 1) return {hitWord, hit};
  if (where.empty()) {
    throw Error("unknown or ambiguous command \"" + std::string(word) + "\": must be " +
                    alternatives(names),
                {"LOOKUP", "COMMAND"});
  }
  throw Error("unknown or ambiguous subcommand \"" + std::string(word) + "\": must be " +
                  alternatives(names),
              {"LOOKUP", "SUBCOMMAND"});
}

namespace {

// Returns whether the words a and b hold the same numbers (one, or a vector of them).
bool sameNumbers(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string x, y;
  int n = 0;
  while (sa >> x) {
    double u = 0, v = 0;
    if (!(sb >> y) || !readReal(x, u) || !readReal(y, v) || !(u == v)) return false;
    ++n;
  }
  return n > 0 && !(sb >> y);
}

// Returns e, or e reworded by the option it is about. The simulation's validity checks word
// their errors by the quantity and print numbers in their shortest form (`bad Young's modulus
// "1e+300": ...`). When the value shown is the value of an option given in this call (the one
// the code names, VALUE YOUNG for -young, or else the only one given with that value), the
// message becomes what the option's own check would say, `bad young "1e300": ...`, the rest
// and the code unchanged.
Error inOptionWords(const Error& e, const ArgStack& stack) {
  const std::vector<std::string>& code = e.code();
  if (code.size() < 3 || code[1] != "VALUE") return e;
  std::string named = code[2];
  std::transform(named.begin(), named.end(), named.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  const std::string msg = e.what();
  const std::size_t open = msg.find('"');
  const std::size_t close = open == std::string::npos ? open : msg.find("\": ", open + 1);
  if (msg.rfind("bad ", 0) != 0 || close == std::string::npos) return e;
  const std::string shown = msg.substr(open + 1, close - open - 1);
  const Slot* hit = nullptr;
  int hits = 0;
  for (const Slot& s : stack.slots()) {
    if (s.param->positional || !s.given || s.words.size() != 1) continue;
    if (!sameNumbers(shown, s.words[0])) continue;
    if (s.param->name == named) {
      hit = &s;
      hits = 1;
      break;
    }
    hit = &s;
    ++hits;
  }
  if (hits != 1) return e;
  return Error("bad " + hit->param->name + " \"" + hit->words[0] + "\": " + msg.substr(close + 3),
               std::vector<std::string>(code.begin() + 1, code.end()));
}

}  // namespace

Value Registry::invoke(const std::vector<std::string>& words, Context& ctx) const {
  Value result;
  invoke(words, ctx, [&](Value&& v, bool) { result = std::move(v); });
  return result;
}

void Registry::invoke(const std::vector<std::string>& words, Context& ctx,
                      const Deliver& deliver) const {
  const Node* n = &root_;
  std::string where;
  std::size_t i = 0;
  while (!n->command) {
    if (i >= words.size()) {
      if (where.empty()) throw Error("wrong # args: should be \"command ?arg ...?\"", {"ARGS"});
      throw Error("wrong # args: should be \"" + where + " subcommand ?arg ...?\"", {"ARGS"});
    }
    if (!where.empty() && words[i] == "-help") return deliver(groupHelp(*n, where), false);
    if (takesShorthand(*n, words[i])) {
      // The word is the shorthand's first argument: it stays in words.
      where += " " + n->shorthandWord;
      n = n->children.find(n->shorthandWord)->second.get();
      continue;
    }
    auto [word, next] = child(*n, words[i], where);
    where = where.empty() ? word : where + " " + word;  // the full word, not the prefix typed
    n = next;
    ++i;
  }
  const Command& c = *n->command;
  std::vector<std::string> rest(words.begin() + long(i), words.end());
  ArgStack stack(c);
  // Phase 1: parse.
  if (!CommandLine(c, std::move(rest)).parse(stack)) return deliver(c.helpText(), false);
  if (c.needsScene) ctx.requireScene();
  if (c.onRanks == OnRanks::Refused && ctx.distributed()) {
    throw Error("\"" + where +
                    "\" is not available once the scene is distributed over MPI ranks (see "
                    "\"Distributed runs\" in doc/commands.md)",
                {"MPI", "UNSUPPORTED"});
  }
  const bool exclusive = c.changesScene || c.needsIdle;
  if (exclusive && !ctx.busyWith.empty()) {
    throw Error("can't use \"" + where + "\" while \"" + ctx.busyWith +
                    "\" is running: a script run from inside it may read the scene, not change it",
                {"STATE", "BUSY"});
  }
  // The check phase too: it may evaluate a script (a load's expression at its start time).
  struct Hold {
    std::string& busy;
    bool held;
    ~Hold() {
      if (held) busy.clear();
    }
  } hold{ctx.busyWith, exclusive};
  if (exclusive) ctx.busyWith = where;
  struct Interruptible {
    Context& ctx;
    bool on;
    ~Interruptible() {
      if (on) ctx.endInterruptible();
    }
  } interruptible{ctx, c.interruptible || !c.changesScene};
  // A pure query is interruptible wherever its loops poll: stopped anywhere, it changed nothing.
  if (interruptible.on) ctx.beginInterruptible();
  try {
    // Phase 2: check.
    PipeLine::check(c, stack, ctx);
    Call call(c, stack, ctx);
    if (c.check) c.check(call);
    // Phase 3: execute.
    if (c.changesScene) ++ctx.changes;
    deliver(c.execute ? c.execute(call) : Value(), !c.changesScene);
  } catch (const Error& e) {
    throw inOptionWords(e, stack);
  }
}

std::string Registry::groupHelp(const Node& n, const std::string& where) const {
  std::string s;
  const std::size_t width = helpWidth();
  if (!n.summary.empty()) s += wrapText(where + ": " + n.summary, width, 0, 0) + "\n";
  std::size_t w = 0;
  std::vector<std::pair<std::string, std::string>> rows;
  for (const auto& [word, c] : n.children) {
    std::string left = where.empty() ? word : where + " " + word;
    std::string right = c->command ? c->command->summary : c->summary;
    rows.emplace_back(left, right);
    w = std::max(w, left.size());
  }
  for (auto& [l, r] : rows) s += helpRow(l, w, r, width);
  if (!n.shorthandWord.empty()) {
    s += '\n';
    s += shorthandLine(n, where);
    s += '\n';
  }
  s += '\n';
  if (where.empty()) {
    s += wrapText("`help <command>` or `<command> -help` describes a command; unique "
                  "prefixes of subcommands and options are accepted.",
                  width, 0, 0);
  } else {
    s += wrapText("`help " + where + " <subcommand>` describes a subcommand.", width, 0, 0);
  }
  return s;
}

std::string Registry::help(const std::vector<std::string>& topic) const {
  const Node* n = &root_;
  std::string where;
  for (const std::string& w : topic) {
    if (n->command) {
      throw Error("no help for \"" + w + "\": " + n->command->fullName() + " has no subcommands",
                  {"LOOKUP", "COMMAND"});
    }
    auto [word, next] = child(*n, w, where);
    where = where.empty() ? word : where + " " + word;
    n = next;
  }
  if (n->command) return n->command->helpText();
  return groupHelp(*n, where);
}

namespace {

// Returns the paths that complete partial as a file (folders too, with a trailing "/", since a
// file may be inside one) or, with foldersOnly, as a folder. Hidden entries only when partial's
// last part starts with a dot. Reads the file system only.
std::vector<std::string> pathCompletions(std::string_view partial, bool foldersOnly) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  const std::string text(partial);
  const std::size_t slash = text.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : text.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? text : text.substr(slash + 1);
  std::error_code ec;
  fs::directory_iterator it(dir.empty() ? fs::path(".") : fs::path(dir), ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!startsWith(name, base) || (name[0] == '.' && (base.empty() || base[0] != '.'))) continue;
    std::error_code e2;
    const bool folder = it->is_directory(e2);
    if (folder) {
      out.push_back(dir + name + "/");
    } else if (!foldersOnly) {
      out.push_back(dir + name);
    }
    if (out.size() > 1000) break;  // a huge folder: the first thousand are plenty to list
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::vector<std::string> Registry::complete(const std::vector<std::string>& before,
                                            std::string_view partial, const Context& ctx) const {
  std::vector<std::string> out;
  const Node* n = &root_;
  std::size_t i = 0;
  while (!n->command && i < before.size()) {
    auto it = n->children.find(before[i]);
    if (it == n->children.end()) {
      try {
        n = child(*n, before[i], "x").second;
      } catch (const Error&) {
        return out;
      }
    } else {
      n = it->second.get();
    }
    ++i;
  }
  auto offer = [&](const std::vector<std::string>& words) {
    for (const std::string& w : words)
      if (startsWith(w, partial)) out.push_back(w);
  };
  if (!n->command) {
    for (const auto& [w, c] : n->children)
      if (startsWith(w, partial)) out.push_back(w);
    return out;
  }
  const Command& c = *n->command;
  auto values = [&](const Param& p) {
    std::vector<std::string> v = p.type.choices;
    const std::string& label = p.type.label;
    if (startsWith(label, "file") || label == "folder") {
      auto paths = pathCompletions(partial, label == "folder");
      v.insert(v.end(), paths.begin(), paths.end());
    }
    if (p.type.candidates) {
      try {
        auto more = p.type.candidates(ctx);
        v.insert(v.end(), more.begin(), more.end());
      } catch (...) {
      }
    }
    return v;
  };
  // After an option that takes a value: complete the value.
  if (i < before.size() && before.back().size() > 1 && before.back()[0] == '-') {
    try {
      const Param& p = CommandLine::matchOption(c, before.back());
      if (!p.flag) {
        offer(values(p));
        return out;
      }
    } catch (const Error&) {
    }
  }
  // The positional arguments still to fill.
  std::size_t given = before.size() - i;
  std::size_t k = 0;
  for (const Param& p : c.params) {
    if (!p.positional) continue;
    if (k == given && !(partial.size() > 0 && partial[0] == '-')) {
      offer(values(p));
      if (!p.optional && !p.variadic) return out;
    }
    ++k;
  }
  std::vector<std::string> opts = c.optionNames();
  opts.push_back("-help");
  offer(opts);
  return out;
}

std::string Registry::markdown() const {
  std::string s =
      "# demlab command reference\n\n"
      "Generated by the build from the command declarations (`demlab --markdown`); do not edit.\n"
      "Every command also answers `help <command>` and `<command> -help`. Options are `-name "
      "value`\n"
      "and may be shortened to any unique prefix. Errors carry an `-errorcode` list starting with\n"
      "`DEMLAB`. Lengths are in metres, times in seconds, masses in kilograms (SI throughout).\n\n";
  for (const auto& [word, n] : root_.children) {
    s += "## " + word + "\n\n";
    if (!n->summary.empty()) s += n->summary + "\n\n";
    if (!n->shorthandWord.empty()) s += shorthandLine(*n, word) + "\n\n";
    if (n->command) {
      s += n->command->markdown();
      continue;
    }
    std::vector<const Node*> stack{n.get()};
    while (!stack.empty()) {
      const Node* m = stack.back();
      stack.pop_back();
      std::vector<const Node*> kids;
      for (const auto& [w, c] : m->children) kids.push_back(c.get());
      for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back(*it);
      if (m->command) s += m->command->markdown();
    }
  }
  return s + distributedMarkdown();
}

std::string Registry::distributedMarkdown() const {
  std::vector<std::string> alike, collective;
  for (const Command* c : commands()) {
    std::string code = "`";
    code += c->fullName();
    code += '`';
    if (c->onRanks == OnRanks::Alike) alike.push_back(code);
    if (c->onRanks == OnRanks::Collective) collective.push_back(code);
  }
  std::sort(alike.begin(), alike.end());
  std::sort(collective.begin(), collective.end());
  auto join = [](const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& w : v) out += (out.empty() ? "" : ", ") + w;
    return out;
  };
  return "## Distributed runs\n\n"
         "`mpirun -np N demlab script.tcl` runs the script on every rank. Until the first "
         "`sim run` or `sim step` every rank builds the whole scene alike; that run spreads it "
         "over the ranks (each keeps the elements of its box of a recursive coordinate "
         "bisection, with copies of its neighbours' elements within reach), or fails with "
         "`MPI UNSUPPORTED` on every rank when the scene has what distributed runs do not "
         "support yet (2D, element shapes, bonds, mesh walls, periodic boundaries, sources, "
         "sinks, behaviors other than gravity, loads and torque ramps, outputs other than "
         "`dump every`, `snapshot every` and `series every`). Element ids, names and tags "
         "stay what the script gave them, alike on every rank. `dump vtk` and `dump every` write "
         "each rank's "
         "elements and contacts as a piece under one `.pvtp`; snapshots are drawn by rank 0 "
         "from every rank's elements. Rank 0 alone "
         "writes standard output; `sim ranks` tells a script its rank. A script that fails the "
         "same way on every rank ends with its error once; a rank failing alone aborts the run "
         "after 10 s rather than leaving the others waiting.\n\n"
         "Once the scene is distributed, these act alike on every rank: " +
         join(alike) +
         ".\n\nThese are collective, every rank gets the whole scene's answer (element lists "
         "in the order of the ids, a tag's in the tag's order): " +
         join(collective) +
         ".\n\nEvery other command fails with `MPI UNSUPPORTED` on every rank, changing "
         "nothing.\n";
}

std::vector<const Command*> Registry::commands() const {
  std::vector<const Command*> out;
  for (const Command& c : commands_) out.push_back(&c);
  return out;
}

}  // namespace demlab::cmd
