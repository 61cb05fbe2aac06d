// demlab: the executable. With no arguments, an interactive console (libedit) on a terminal
// or commands from stdin otherwise; `demlab script.tcl ?arg ...?` runs a batch script with
// argv, argc and argv0 set and exits non-zero, printing the error, when it fails.
// `demlab --markdown` prints the command reference (the build writes doc/commands.md with it);
// `demlab --declarations` prints the declarations it is made from, as data.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "core/thread_pool.hpp"
#include "app/console.hpp"
#include "cmd/commands/commands.hpp"
#include "mpi/communicator.hpp"
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

// How long a rank whose script failed waits for the others to fail with it (the scene's
// errors come on every rank at the same command, within a step's time) before it aborts the
// run, which they may be stepping without it.
constexpr double kFailurePatience = 10.0;

// MPI for the process's life when mpirun started it; ended before the process exits.
std::optional<demlab::mpi::Session> mpiSession;

// At Tcl's exit (the script's end or its `exit`): MPI's end, which a rank must reach before it
// leaves, or the others are stopped.
void endMpi(void*) { mpiSession.reset(); }

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
  // Started as one of several ranks by mpirun: every rank runs the script, the first run
  // spreads the scene over them (doc/commands.md, "Distributed runs"). A build without MPI
  // would run it once per rank, each writing the same files.
  const int ranks = launchedRanks();
  if (ranks > 1 && !mpi::built()) {
    std::fprintf(stderr,
                 "demlab: started as one of %d ranks by mpirun, but built without MPI "
                 "(libopenmpi-dev): run one demlab per scene\n",
                 ranks);
    return 2;
  }
  mpiSession.emplace(&argc, &argv);
  const mpi::Communicator& world = mpi::Communicator::world();
  if (world.distributed() && argc < 2) {
    if (world.rank() == 0) {
      std::fprintf(stderr,
                   "demlab: under mpirun demlab runs a script (mpirun -np N demlab "
                   "script.tcl): mpirun gives the console's input to one rank alone\n");
    }
    mpiSession.reset();
    return 2;
  }
  // A bad $DEMLAB_THREADS is named once, here; the run goes on with every core.
  const char* threadsError = nullptr;
  ThreadPool::threadsFromEnvironment(&threadsError);
  if (threadsError != nullptr) std::fprintf(stderr, "demlab: warning: %s\n", threadsError);
  Tcl_FindExecutable(argv[0]);
  // Every rank runs the script; rank 0 alone speaks on stdout (puts, run reports). Errors and
  // warnings stay on every rank's stderr.
  if (world.rank() != 0) {
    Tcl_Channel null = Tcl_OpenFileChannel(nullptr, "/dev/null", "w", 0);
    if (null != nullptr) Tcl_SetStdChannel(null, TCL_STDOUT);
  }
  Tcl_CreateExitHandler(endMpi, nullptr);
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
    std::string failure;
    if (code != TCL_OK) {
      const char* info = Tcl_GetVar(interp, "errorInfo", TCL_GLOBAL_ONLY);
      const char* ecode = Tcl_GetVar(interp, "errorCode", TCL_GLOBAL_ONLY);
      failure = info ? info : Tcl_GetStringResult(interp);
      if (ecode && std::strncmp(ecode, "DEMLAB INTERRUPTED", 18) == 0) {
        failure += std::string("\ndemlab: ") + argv[1] + " interrupted by Ctrl-C";
      }
      status = 1;
    }
    // The ranks agree on how the script ended; the lowest failed rank tells why.
    const std::string prefix = world.distributed() ? "demlab: rank " +
                                                         std::to_string(world.rank()) + " of " +
                                                         std::to_string(world.size()) + ": "
                                                   : "";
    const mpi::Session::Ending end = mpiSession->endScript(
        status, kFailurePatience,
        prefix + failure + "\ndemlab: the other ranks did not fail with it: aborting the run");
    if (status != 0 && end.firstFailed == world.rank()) {
      std::fprintf(stderr, "%s\n", (world.rank() == 0 ? failure : prefix + failure).c_str());
    }
    status = end.worst;
  } else if (tty) {
    status = app::runConsole(interp, argv[0]);
  } else {
    status = app::runStdin(interp);
  }
  Tcl_Exit(status);
}
