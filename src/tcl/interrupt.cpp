// SIGINT handling for runs and scripts (see binding.hpp). Only async-signal-safe work happens
// in the handler: atomic stores and Tcl_AsyncMark.
#include <signal.h>

#include "tcl/binding.hpp"

namespace demlab::tcl {

namespace {

std::atomic<std::atomic<bool>*> g_stop{nullptr};  // the running Session's stop flag
std::atomic<bool> g_evaluating{false};
std::atomic<bool> g_promptInterrupt{false};
Tcl_AsyncHandler g_async = nullptr;
bool g_permanent = false;
struct sigaction g_saved;
int g_runDepth = 0;

extern "C" void onSigint(int) {
  if (std::atomic<bool>* f = g_stop.load()) {
    f->store(true);
  } else if (g_evaluating.load() && g_async) {
    Tcl_AsyncMark(g_async);
  } else {
    g_promptInterrupt.store(true);
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
  if (!interp) return code;
  Tcl_SetObjResult(interp, Tcl_NewStringObj("interrupted", -1));
  Tcl_SetErrorCode(interp, "DEMLAB", "INTERRUPTED", nullptr);
  return TCL_ERROR;
}

}  // namespace

void installInterruptHandler(Tcl_Interp*) {
  if (!g_async) g_async = Tcl_AsyncCreate(asyncProc, nullptr);
  g_permanent = true;
  install(nullptr);
}

void setEvaluating(bool evaluating) {
  g_evaluating.store(evaluating);
}

bool takePromptInterrupt() {
  return g_promptInterrupt.exchange(false);
}

// The Session hooks around a run (used by binding.cpp).
void beginRun(std::atomic<bool>* stop) {
  if (g_runDepth++ == 0) {
    if (!g_permanent) install(&g_saved);
    g_stop.store(stop);
  }
}

void endRun() {
  if (--g_runDepth == 0) {
    g_stop.store(nullptr);
    if (!g_permanent) sigaction(SIGINT, &g_saved, nullptr);
  }
}

}  // namespace demlab::tcl
