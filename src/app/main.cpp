// demlab: the executable. With no arguments, an interactive console (libedit) on a terminal
// or commands from stdin otherwise; `demlab script.tcl ?arg ...?` runs a batch script with
// argv, argc and argv0 set and exits non-zero, printing the error, when it fails.
// `demlab --markdown` prints the command reference (the build writes doc/commands.md with it);
// `demlab --declarations` prints the declarations it is made from, as data.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/thread_pool.hpp"
#include "app/console.hpp"
#include "cmd/commands/commands.hpp"
#include "tcl/binding.hpp"

namespace {

const char* kUsage =
    "usage: demlab                     interactive console (commands from stdin when not a "
    "terminal)\n"
    "       demlab script.tcl ?arg ...?  run a batch script\n"
    "       demlab --markdown          print the command reference (Markdown)\n"
    "       demlab --declarations      print the command declarations as a Tcl list of dicts\n"
    "       demlab --help | --version\n";

// Returns the number of processes the launcher started this one among (mpirun's, OpenMPI's
// OMPI_COMM_WORLD_SIZE; MPICH's and Slurm's PMI_SIZE), or 1.
int launchedRanks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* v = std::getenv(name);
    if (v == nullptr) continue;
    char* end = nullptr;
    const long n = std::strtol(v, &end, 10);
    if (end != v && *end == '\0' && n > 1) return n > 1000000 ? 1000000 : static_cast<int>(n);
  }
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace demlab;
  if (argc > 1 && std::strcmp(argv[1], "--markdown") == 0) {
    std::fputs(cmd::commandRegistry().markdown().c_str(), stdout);
    std::fputs(tcl::helpersMarkdown().c_str(), stdout);
    return 0;
  }
  if (argc > 1 && std::strcmp(argv[1], "--declarations") == 0) {
    std::puts(cmd::toString(cmd::commandRegistry().declarations({})).c_str());
    return 0;
  }
  if (argc > 1 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (argc > 1 && std::strcmp(argv[1], "--version") == 0) {
    std::printf("demlab %s\n", DEMLAB_PKG_VERSION);
    return 0;
  }
  // Started as one of several ranks by mpirun: each would run the whole script as its own
  // serial scene and write the same files at once. Refused until the distributed run exists
  // (doc/plans/mpi.md).
  if (const int ranks = launchedRanks(); ranks > 1) {
    std::fprintf(stderr,
                 "demlab: started as one of %d ranks by mpirun; distributed runs are not built "
                 "yet (doc/plans/mpi.md): run one demlab per scene\n",
                 ranks);
    return 2;
  }
  // A bad $DEMLAB_THREADS is named once, here; the run goes on with every core.
  const char* threadsError = nullptr;
  ThreadPool::threadsFromEnvironment(&threadsError);
  if (threadsError != nullptr) std::fprintf(stderr, "demlab: warning: %s\n", threadsError);
  Tcl_FindExecutable(argv[0]);
  Tcl_Interp* interp = Tcl_CreateInterp();
  bool script = argc > 1;
  bool tty = !script && isatty(0);

  Tcl_Obj* args = Tcl_NewListObj(0, nullptr);
  for (int k = 2; k < argc; ++k)
    Tcl_ListObjAppendElement(nullptr, args, Tcl_NewStringObj(argv[k], -1));
  Tcl_SetVar2Ex(interp, "argv", nullptr, script ? args : Tcl_NewListObj(0, nullptr),
                TCL_GLOBAL_ONLY);
  Tcl_SetVar2Ex(interp, "argc", nullptr, Tcl_NewIntObj(script ? argc - 2 : 0), TCL_GLOBAL_ONLY);
  Tcl_SetVar2Ex(interp, "argv0", nullptr, Tcl_NewStringObj(script ? argv[1] : argv[0], -1),
                TCL_GLOBAL_ONLY);
  Tcl_SetVar2Ex(interp, "tcl_interactive", nullptr, Tcl_NewIntObj(tty ? 1 : 0), TCL_GLOBAL_ONLY);

  if (Tcl_Init(interp) != TCL_OK) {
    std::fprintf(stderr, "demlab: Tcl library not found: %s\n", Tcl_GetStringResult(interp));
  }
  Tcl_StaticPackage(nullptr, "Demlab", Demlab_Init, nullptr);
  if (Demlab_Init(interp) != TCL_OK || Demlab_ImportCommands(interp) != TCL_OK) {
    std::fprintf(stderr, "demlab: %s\n", Tcl_GetStringResult(interp));
    return 2;
  }
  tcl::installInterruptHandler(interp);

  int status = 0;
  if (script) {
    Tcl_Obj* path = Tcl_NewStringObj(argv[1], -1);
    Tcl_IncrRefCount(path);
    tcl::setEvaluating(true);
    int code = Tcl_FSEvalFileEx(interp, path, nullptr);
    if (Tcl_AsyncReady()) code = Tcl_AsyncInvoke(interp, code);
    tcl::setEvaluating(false);
    Tcl_DecrRefCount(path);
    if (code != TCL_OK) {
      const char* info = Tcl_GetVar(interp, "errorInfo", TCL_GLOBAL_ONLY);
      const char* ecode = Tcl_GetVar(interp, "errorCode", TCL_GLOBAL_ONLY);
      std::fprintf(stderr, "%s\n", info ? info : Tcl_GetStringResult(interp));
      if (ecode && std::strncmp(ecode, "DEMLAB INTERRUPTED", 18) == 0) {
        std::fprintf(stderr, "demlab: %s interrupted by Ctrl-C\n", argv[1]);
      }
      status = 1;
    }
  } else if (tty) {
    status = app::runConsole(interp, argv[0]);
  } else {
    status = app::runStdin(interp);
  }
  Tcl_Exit(status);
}
