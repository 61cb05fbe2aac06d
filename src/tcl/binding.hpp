// The Tcl binding: one Tcl command per top-level word of the command registry, a Session per
// interpreter, cmd::Value to Tcl_Obj, demlab::Error to a Tcl error with -errorcode, and the
// SIGINT handling that stops a run at a step boundary. Compiled against the stubs table, so
// the same objects serve the executable and the loadable package.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include <tcl.h>

#include "cmd/session.hpp"
#include "cmd/value.hpp"
#include "core/interrupt.hpp"

extern "C" {
// The package's entry point (`load libdemlab.so Demlab`): defines the commands in ::demlab
// (exported; the ensemble ::demlab too unless a command of that name exists), provides the
// package, evaluates the Tcl-level library. Returns TCL_OK or TCL_ERROR with a message. There
// is no Demlab_SafeInit: the commands read and write files, so safe interpreters can't load it.
int Demlab_Init(Tcl_Interp* interp);
// Imports the package's commands (not its helper procedures) into the global namespace, as the
// demlab executable does for its console and scripts. Returns TCL_ERROR with Tcl's message
// when a global command of one of their names exists (none is replaced).
int Demlab_ImportCommands(Tcl_Interp* interp);
}

namespace demlab::tcl {

// Returns the Markdown reference of the Tcl library's exported helpers (demlab::settle, ...),
// from the comment above each procedure, for `demlab --markdown`. Changes nothing.
std::string helpersMarkdown();

// Returns the Session of an interpreter where Demlab_Init ran, or nullptr.
cmd::Session* sessionOf(Tcl_Interp* interp);

// Returns a new Tcl_Obj (refcount 0) holding v; takes v's large integer arrays over (v is a
// command's result, consumed). With a poll, calls it before each element of every list, so
// Ctrl-C can abandon a large result: throws demlab::Error {INTERRUPTED} then, having freed what
// it built.
Tcl_Obj* toObj(cmd::Value& v, InterruptPoll* poll = nullptr);

// Returns the completions of the word ending at the end of `line` (console tab completion):
// demlab commands, subcommands, options and option values from the declarations, and other Tcl
// commands for the first word of a command.
std::vector<std::string> completions(Tcl_Interp* interp, const std::string& line,
                                     std::string& partial);

// SIGINT. In the executable the handler is installed once (installInterruptHandler): during a
// run it sets the stop flag; during other evaluation it makes the script fail with
// `interrupted` (DEMLAB INTERRUPTED) at the next command; at the prompt it only sets a flag the
// console takes with takePromptInterrupt. In a plain tclsh the handler is installed only for
// the duration of each run, so tclsh keeps its own behaviour otherwise.
void installInterruptHandler(Tcl_Interp* interp);
void setEvaluating(bool evaluating);
// Returns whether a SIGINT met the prompt since the last call, and clears that (and drains the
// wake-up pipe).
bool takePromptInterrupt();
// Returns the read end of a pipe that becomes readable when a SIGINT meets the prompt (after
// installInterruptHandler; -1 before or if no pipe could be made). A console waits on it with
// its input: a signal that arrives before the console's read begins cannot interrupt that read.
int promptWakeFd();

}  // namespace demlab::tcl
