// The command system of thesis chapter 12: each command is declared once (Command: its words,
// its parameters with their pipes, defaults, units and help), and a call goes through three
// phases:
//   1. parse   - CommandLine matches the words of the call against the declaration and lays
//                them on the ArgStack, one slot per parameter (PipeSource: a word or a default);
//   2. check   - the PipeLine sends each slot through its pipe (conversion, range, lookups) and
//                then runs the command's own cross-argument check; every error is raised here;
//   3. execute - the command runs; it pops typed values from the ArgStack, or lets the PipeLine
//                hand them to their destinations (PipeDest: a member of a Def struct).
// Only phase 3 changes anything, and it is written so that a failing call changes nothing.
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeinfo>
#include <vector>

#include "cmd/pipe.hpp"
#include "cmd/value.hpp"
#include "core/error.hpp"

namespace demlab::cmd {

// What commands act on. The application derives its Session from it; the command system only
// needs the dimension (for vector pipes).
struct Context {
  virtual ~Context() = default;
  // Returns the number of components of a vector argument (the simulation's dimension).
  virtual int dimension() const { return 3; }
  // Throws demlab::Error {STATE NOSIM} when there is no scene for a command that needs one.
  virtual void requireScene() const {}
  // The command that changes the scene and is executing now ("sim run"), or "". A script it
  // runs (a callback, a load's expression, a redirected puts) may read the scene but not
  // change or replace it: the running command holds the scene and its parts.
  std::string busyWith;
  // Returns true when the scene is spread over the ranks of an MPI run: commands declared
  // OnRanks::Refused then fail with {MPI UNSUPPORTED}.
  virtual bool distributed() const { return false; }
  // Counts the commands that changed or may have changed the scene (those declared so, when
  // they reached their execute phase): a watcher (the viewer) redraws when it moves.
  std::uint64_t changes = 0;
  // Bracket the check and execute phases of a command declared interruptible: in between,
  // Ctrl-C sets the flag demlab::interruptRequested() reads. By default nothing can interrupt.
  virtual void beginInterruptible() {}
  virtual void endInterruptible() {}
};

struct Param {
  std::string name;  // without the leading "-" for options
  PipeType type;
  std::string help;
  bool positional = false;
  bool required = false;
  bool flag = false;      // an option that takes no value (present: true)
  bool variadic = false;  // a last positional that takes all remaining words (one or more)
  bool optional = false;  // a positional that may be left out (only at the end)
  std::string def;        // default word, converted by the pipe like a given one
  bool hasDefault = false;
  // PipeDest: stores the typed value into the destination struct (see Command::fill).
  std::function<void(void* dest, const std::any& value)> dest;
  const std::type_info* destType = nullptr;

  // Builders, for chaining after Command::option / Command::arg.
  Param& byDefault(std::string word) {
    def = std::move(word);
    hasDefault = true;
    return *this;
  }
  Param& require() {
    required = true;
    return *this;
  }
  template <class Def, class T>
  Param& to(T Def::*member);

  // Returns the word naming the parameter in a usage string: "-radius r", "name", "?id ...?".
  std::string usage() const;
};

class Call;

// What a command does once the scene is spread over the ranks of an MPI run (`mpirun -np N
// demlab script.tcl`: every rank runs the script; the first run spreads the scene). Before
// that every command acts alike on every rank's whole copy of the scene.
enum class OnRanks {
  Refused,     // {MPI UNSUPPORTED} on every rank: it reads or changes one rank's elements
  Alike,       // reads or changes only what every rank holds alike (time, materials, settings)
  Collective,  // every rank runs it together and gets the same answer (summed or gathered)
};

struct Command {
  std::vector<std::string> path;  // {"element", "add"}
  std::string summary;            // one line
  std::string details;            // more help text (may be empty)
  std::vector<Param> params;      // positionals (in order) and options
  struct Group {
    std::vector<std::string> names;
    bool requireOne = false;
  };
  std::vector<Group> exclusive;         // at most one (or exactly one) of these options
  bool needsScene = true;               // fails with {STATE NOSIM} before a simulation exists
  bool changesScene = true;             // false for pure queries (shown in help)
  // Refused while another command that changes the scene runs (see Context::busyWith), like
  // those that change it, although it does not: it changes what the running command uses.
  bool needsIdle = false;
  // Its work grows with the scene or its arguments: Ctrl-C stops it, with {INTERRUPTED}, at a
  // point where it has changed nothing (a run: at a step boundary). Its loops poll
  // demlab::pollInterrupt (core/interrupt.hpp). Pure queries (changesScene false) are always
  // interruptible, and so is the conversion of their result to Tcl.
  bool interruptible = false;
  OnRanks onRanks = OnRanks::Refused;  // once the scene is distributed
  std::function<void(Call&)> check;     // optional: cross-argument checks, read-only
  std::function<Value(Call&)> execute;  // phase 3

  // Declaration builders. Each returns the new parameter, for chaining.
  Param& arg(std::string name, PipeType type, std::string help);
  Param& optionalArg(std::string name, PipeType type, std::string help);
  Param& variadicArg(std::string name, PipeType type, std::string help);
  Param& option(std::string name, PipeType type, std::string help);
  Param& flag(std::string name, std::string help);
  Command& oneOf(std::vector<std::string> names, bool requireOne);
  Command& onCheck(std::function<void(Call&)> f) {
    check = std::move(f);
    return *this;
  }
  Command& run(std::function<Value(Call&)> f) {
    execute = std::move(f);
    return *this;
  }

  // Returns the full command name ("element add").
  std::string fullName() const;
  // Returns `element add name ?-option value ...?`, the usage string of wrong # args.
  std::string usage() const;
  // Returns the parameter named `name`, or nullptr.
  const Param* find(std::string_view name) const;
  // Returns the option names, with "-", in declaration order.
  std::vector<std::string> optionNames() const;
  // Returns the help text (what `help element add` prints).
  std::string helpText() const;
  // Returns the Markdown section for doc/commands.md.
  std::string markdown() const;
  // Returns the declaration as data (declaration.cpp): a dict of command, needsscene,
  // changesscene, needsidle, onranks (refused|alike|collective), params (a dict per parameter:
  // name, role positional|variadic|option|flag, required, optional, kind real|integer|boolean|
  // text|name|choice|vector|reals|integers|custom, label, unit, min, max, minopen, maxopen,
  // length, choices, default, hasdefault) and exclusive (a dict per group: names, requireone).
  // Changes nothing.
  Value declaration() const;
};

// One slot per parameter: the word it was given (PipeSource), then its typed value.
struct Slot {
  const Param* param = nullptr;
  std::vector<std::string> words;  // the word(s) given; empty if not given
  bool given = false;
  std::any value;  // after the check phase; empty if neither given nor defaulted
};

// The thesis's ArgStack: the arguments of one call, raw after parsing, typed after checking.
class ArgStack {
 public:
  explicit ArgStack(const Command& c);
  Slot& slot(std::string_view name);
  const Slot& slot(std::string_view name) const;
  std::vector<Slot>& slots() { return slots_; }
  const std::vector<Slot>& slots() const { return slots_; }
  // Options given as flags, in the order the call gave them.
  std::vector<std::string>& flagOrder() { return flagOrder_; }
  const std::vector<std::string>& flagOrder() const { return flagOrder_; }

 private:
  std::vector<Slot> slots_;
  std::vector<std::string> flagOrder_;
};

// The thesis's CommandLine: parses the words of a call (after the command's own words) against
// the declaration onto an ArgStack. Returns false, leaving the stack as is, if the call asks for
// help (`-help` where an option may stand); throws demlab::Error {ARGS} or {OPTION} otherwise.
class CommandLine {
 public:
  CommandLine(const Command& c, std::vector<std::string> words)
      : cmd_(c), words_(std::move(words)) {}
  bool parse(ArgStack& stack) const;

  // Returns the option parameter that `word` names (exact or unique prefix). Throws
  // demlab::Error {OPTION}: `bad option "-x": must be -a, -b, or -c`, or `ambiguous option`.
  static const Param& matchOption(const Command& c, std::string_view word);

 private:
  const Command& cmd_;
  std::vector<std::string> words_;
};

// The thesis's PipeLine: runs every slot through its pipe (check), and hands values to their
// destinations (execute).
class PipeLine {
 public:
  // Check phase: converts and checks every slot, then the exclusive groups. Throws
  // demlab::Error; changes only the stack.
  static void check(const Command& c, ArgStack& stack, const Context& ctx);
  // Execute phase: stores every value that has a destination of type Def into def.
  static void fill(const ArgStack& stack, void* def, const std::type_info& type);
};

// What a command sees in its check and execute phases.
class Call {
 public:
  Call(const Command& c, ArgStack& s, Context& ctx) : cmd_(c), stack_(s), ctx_(ctx) {}

  const Command& command() const { return cmd_; }
  Context& context() { return ctx_; }
  const Context& context() const { return ctx_; }
  ArgStack& stack() { return stack_; }

  // Returns true if the parameter was given in the call (not defaulted).
  bool given(std::string_view name) const { return stack_.slot(name).given; }
  // Returns true if the parameter has a value (given or defaulted).
  bool has(std::string_view name) const { return stack_.slot(name).value.has_value(); }
  // Returns the typed value of a parameter. Throws std::bad_any_cast on a declaration bug.
  template <class T>
  const T& get(std::string_view name) const {
    return std::any_cast<const T&>(stack_.slot(name).value);
  }
  double real(std::string_view n) const { return get<double>(n); }
  std::int64_t integer(std::string_view n) const { return get<std::int64_t>(n); }
  const std::string& str(std::string_view n) const { return get<std::string>(n); }
  const std::vector<double>& vec(std::string_view n) const { return get<std::vector<double>>(n); }
  bool flag(std::string_view n) const { return has(n) && get<bool>(n); }
  // Returns the values of a variadic positional.
  template <class T>
  std::vector<T> all(std::string_view name) const {
    std::vector<T> out;
    for (const std::any& a : get<std::vector<std::any>>(name)) out.push_back(std::any_cast<T>(a));
    return out;
  }
  // The flags given, in call order.
  const std::vector<std::string>& flagOrder() const { return stack_.flagOrder(); }

  // PipeDest: fills the members of def that parameters were bound to with Param::to.
  template <class Def>
  void fill(Def& def) const {
    PipeLine::fill(stack_, &def, typeid(Def));
  }

  // What the check phase prepared for the execute phase (a Def built and checked, a count).
  std::any prepared;

  // Throws demlab::Error {VALUE <PARAM>}: `bad <param> "<word>": <why>`.
  [[noreturn]] void bad(std::string_view param, std::string_view why) const;

 private:
  const Command& cmd_;
  ArgStack& stack_;
  Context& ctx_;
};

// Stores a typed pipe value into a destination of type T, converting between the value kinds
// (double, int64, bool, string, vector of reals) and T (arithmetic, string, std::vector, or a
// fixed-size Eigen vector). Throws demlab::Error {INTERNAL} on a declaration mismatch.
template <class T>
void assignValue(T& dst, const std::any& v) {
  if constexpr (std::is_same_v<T, bool>) {
    if (auto* b = std::any_cast<bool>(&v)) {
      dst = *b;
      return;
    }
  } else if constexpr (std::is_arithmetic_v<T>) {
    if (auto* d = std::any_cast<double>(&v)) {
      dst = T(*d);
      return;
    }
    if (auto* i = std::any_cast<std::int64_t>(&v)) {
      dst = T(*i);
      return;
    }
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (auto* s = std::any_cast<std::string>(&v)) {
      dst = *s;
      return;
    }
  } else if constexpr (requires { T::RowsAtCompileTime; }) {
    if (auto* x = std::any_cast<std::vector<double>>(&v)) {
      if (int(x->size()) == int(T::RowsAtCompileTime)) {
        for (int k = 0; k < int(x->size()); ++k) dst[k] = (*x)[std::size_t(k)];
        return;
      }
    }
  }
  if (auto* t = std::any_cast<T>(&v)) {
    dst = *t;
    return;
  }
  throw Error(std::string("internal error: parameter value of type ") + v.type().name() +
                  " cannot be stored into " + typeid(T).name(),
              {"INTERNAL"});
}

template <class Def, class T>
Param& Param::to(T Def::*member) {
  dest = [member](void* d, const std::any& v) { assignValue(static_cast<Def*>(d)->*member, v); };
  destType = &typeid(Def);
  return *this;
}

}  // namespace demlab::cmd
