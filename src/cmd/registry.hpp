// The table of commands: a tree of words (ensembles and their subcommands) whose leaves are
// Command declarations. It dispatches a call through the three phases, answers help and
// completion, and writes the Markdown reference, all from the same declarations.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cmd/command.hpp"

namespace demlab::cmd {

class Registry {
 public:
  // Declares the command named by `path` ("element add"): returns it for the declaration to
  // fill. Throws demlab::Error {INTERNAL} if the name is taken or clashes with a group.
  Command& add(std::string_view path, std::string summary);
  // Gives a group of subcommands ("element") its one-line summary.
  void describe(std::string_view group, std::string summary);
  // Lets a word ending in `suffix` that names none of group's subcommands (not even by prefix)
  // stand for `group subcommand word ...`: `snapshot frame.png` for `snapshot write frame.png`.
  // Throws demlab::Error {INTERNAL} if the group or its subcommand is not declared yet.
  void shorthand(std::string_view group, std::string_view subcommand, std::string suffix);

  // Returns the top-level words, sorted: each becomes one Tcl command.
  std::vector<std::string> topWords() const;

  // Runs a call: words[0] is the top-level command. Returns the command's result, or the help
  // text for `-help`. Throws demlab::Error; the three phases guarantee that a call that throws
  // in parse or check changed nothing.
  Value invoke(const std::vector<std::string>& words, Context& ctx) const;

  // Runs a call as invoke does and gives its result to deliver(result, interruptible) before
  // returning, while Ctrl-C can still interrupt the command: interruptible is true for pure
  // queries (Command::changesScene false), whose result may be abandoned half converted (a
  // list of a million contacts takes seconds to become Tcl objects). Throws as invoke does,
  // and whatever deliver throws.
  using Deliver = std::function<void(Value&&, bool interruptible)>;
  void invoke(const std::vector<std::string>& words, Context& ctx, const Deliver& deliver) const;

  // Returns the help for a topic: {} for the overview, {"element"} for a group, {"element",
  // "add"} for a command (unique prefixes accepted). Throws demlab::Error {LOOKUP COMMAND}.
  std::string help(const std::vector<std::string>& topic) const;

  // Returns the completions of `partial`, the word being typed after the complete words
  // `before` (before[0] is the command; empty when completing the command itself).
  std::vector<std::string> complete(const std::vector<std::string>& before,
                                    std::string_view partial, const Context& ctx) const;

  // Returns the Markdown command reference (doc/commands.md).
  std::string markdown() const;
  // Returns the reference's last section: how a script runs under mpirun, and which commands
  // act alike on every rank or collectively once the scene is distributed (the others are
  // refused), from their declarations.
  std::string distributedMarkdown() const;

  // Returns the declarations (Command::declaration) of the commands under a topic ({} for all),
  // in the reference's order. Throws demlab::Error {LOOKUP COMMAND} or {LOOKUP SUBCOMMAND}.
  Value declarations(const std::vector<std::string>& topic) const;

  // Returns every command, in declaration order.
  std::vector<const Command*> commands() const;

 private:
  struct Node {
    std::string summary;
    Command* command = nullptr;
    std::map<std::string, std::unique_ptr<Node>, std::less<>> children;
    std::string shorthandWord, shorthandSuffix;  // Registry::shorthand; empty: none
  };
  // Returns the child of n that `word` names, with its full word (exact or unique prefix). Throws
  // demlab::Error {LOOKUP SUBCOMMAND} (or {LOOKUP COMMAND} at the top) in Tcl's ensemble wording.
  std::pair<std::string, const Node*> child(const Node& n, std::string_view word,
                                            const std::string& where) const;
  std::string groupHelp(const Node& n, const std::string& where) const;
  // Returns true if `word` is n's shorthand (Registry::shorthand): it ends in the suffix and
  // names no subcommand of n.
  static bool takesShorthand(const Node& n, std::string_view word);
  // Returns the sentence describing n's shorthand, for the help and the reference.
  static std::string shorthandLine(const Node& n, const std::string& where);

  Node root_;
  std::deque<Command> commands_;
};

}  // namespace demlab::cmd
