// SIGINT handling for runs and scripts (see binding.hpp). Only async-signal-safe work happens
// in the handler: atomic stores and Tcl_AsyncMark.
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include "tcl/binding.hpp"

namespace demlab::tcl {

namespace {

std::atomic<std::atomic<bool>*> g_stop{nullptr};  // the running Session's stop flag
std::atomic<bool> g_evaluating{false};
std::atomic<bool> g_promptInterrupt{false};
// A SIGINT that came while a script was evaluating but no interruptible command had started:
// the next one to start takes it (beginRun), else Tcl's async handler raises it.
std::atomic<bool> g_pendingAsync{false};
Tcl_AsyncHandler g_async = nullptr;
bool g_permanent = false;
struct sigaction g_saved;
int g_runDepth = 0;
// The prompt's wake-up pipe: the handler writes a byte when a SIGINT meets the prompt, so a
// console polling it with its input (promptWakeFd) wakes even when the signal came before the
// console's read started.
int g_wake[2] = {-1, -1};

extern "C" void onSigint(int) {
  if (std::atomic<bool>* f = g_stop.load()) {
    f->store(true);
  } else if (g_evaluating.load() && g_async) {
    g_pendingAsync.store(true);
    Tcl_AsyncMark(g_async);
  } else {
    g_promptInterrupt.store(true);
    if (g_wake[1] >= 0) {
      const char byte = 1;
      [[maybe_unused]] const ssize_t n = write(g_wake[1], &byte, 1);  // full pipe: already woken
    }
  }
}

void install(struct sigaction* old) {
  struct sigaction sa {};
  sa.sa_handler = onSigint;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a read at the console prompt returns with EINTR
  sigaction(SIGINT, &sa, old);
}

extern "C" int asyncProc(ClientData, Tcl_Interp* interp, int code) {
  // Taken already by a command that started just after the signal (and was interrupted).
  if (!g_pendingAsync.exchange(false)) return code;
  if (!interp) return code;
  Tcl_SetObjResult(interp, Tcl_NewStringObj("interrupted", -1));
  Tcl_SetErrorCode(interp, "DEMLAB", "INTERRUPTED", nullptr);
  return TCL_ERROR;
}

}  // namespace

void installInterruptHandler(Tcl_Interp*) {
  if (!g_async) g_async = Tcl_AsyncCreate(asyncProc, nullptr);
  g_permanent = true;
  if (g_wake[0] < 0 && pipe2(g_wake, O_NONBLOCK | O_CLOEXEC) != 0) g_wake[0] = g_wake[1] = -1;
  install(nullptr);
}

int promptWakeFd() {
  return g_wake[0];
}

void setEvaluating(bool evaluating) {
  g_evaluating.store(evaluating);
}

bool takePromptInterrupt() {
  const bool taken = g_promptInterrupt.exchange(false);
  if (taken && g_wake[0] >= 0) {
    char drain[64];
    while (read(g_wake[0], drain, sizeof drain) > 0) {
    }
  }
  return taken;
}

// The Session hooks around a run (used by binding.cpp).
void beginRun(std::atomic<bool>* stop) {
  if (g_runDepth++ == 0) {
    if (!g_permanent) install(&g_saved);
    g_stop.store(stop);
    // A Ctrl-C that came just before the command started is its: it stops at its first poll
    // (otherwise Tcl would raise it only after the command, which may run for hours).
    if (g_pendingAsync.exchange(false)) stop->store(true);
  }
}

void endRun() {
  if (--g_runDepth == 0) {
    g_stop.store(nullptr);
    if (!g_permanent) sigaction(SIGINT, &g_saved, nullptr);
  }
}

}  // namespace demlab::tcl
