// The interactive console (a tclsh-like REPL with libedit) and the plain-stdin reader.
#pragma once

#include <tcl.h>

namespace demlab::app {

// Runs the console on a terminal: prompt, multi-line input (Tcl_CommandComplete), history
// (~/.demlab_history), emacs-style line editing and tab completion. Ctrl-C at the prompt
// clears the input; during a command it interrupts it. Returns the exit status (0 at EOF).
int runConsole(Tcl_Interp* interp, const char* argv0);

// Evaluates commands read from a non-terminal stdin, one complete command at a time, printing
// errors (not results, as tclsh) to stderr. Returns 1 if any command failed, else 0.
int runStdin(Tcl_Interp* interp);

// Evaluates one command with the SIGINT handling of a script; returns the Tcl code.
int evaluate(Tcl_Interp* interp, const char* script);

}  // namespace demlab::app
