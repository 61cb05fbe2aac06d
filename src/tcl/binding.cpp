#include "tcl/binding.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/background_work.hpp"
#include "core/free_aside.hpp"
#include "core/validity.hpp"
#include "mpi/communicator.hpp"
#include "tcl/int_list_obj.hpp"
#include "physics/material.hpp"

extern const char* const demlabTclLibrary;  // tcl/demlab.tcl, compiled in (generated)

#ifndef DEMLAB_PKG_VERSION
#define DEMLAB_PKG_VERSION "0.1"
#endif

namespace demlab::tcl {

// The fewest integers a result hands over unconverted (tcl/int_list_obj.hpp): fewer are made
// Tcl objects at once, a few milliseconds.
constexpr std::size_t kLazyIntList = 16384;

void beginRun(std::atomic<bool>* stop);
void endRun();

namespace {

constexpr const char* kAssocKey = "demlab::session";

struct Bound {
  cmd::Session* session;
  std::string word;
};

// The Session and what the binding keeps beside it.
struct InterpState {
  cmd::Session session;
  Tcl_Interp* interp = nullptr;
};

InterpState* stateOf(Tcl_Interp* interp) {
  return static_cast<InterpState*>(Tcl_GetAssocData(interp, kAssocKey, nullptr));
}

extern "C" void deleteState(ClientData cd, Tcl_Interp*) {
  delete static_cast<InterpState*>(cd);
}
extern "C" void deleteBound(ClientData cd) {
  delete static_cast<Bound*>(cd);
}

// Sets the interpreter's result and -errorcode from e; returns TCL_ERROR.
int fail(Tcl_Interp* interp, const std::string& message, const std::vector<std::string>& code) {
  Tcl_SetObjResult(interp, Tcl_NewStringObj(message.c_str(), int(message.size())));
  Tcl_Obj* list = Tcl_NewListObj(0, nullptr);
  for (const std::string& w : code)
    Tcl_ListObjAppendElement(nullptr, list, Tcl_NewStringObj(w.c_str(), int(w.size())));
  Tcl_SetObjErrorCode(interp, list);
  return TCL_ERROR;
}

// A time function that evaluates `apply {t {expr {EXPR}}} $t` in the interpreter. An error
// during a run is recorded in the Session and stops the run; the function then returns 0.
struct ExprFn {
  Tcl_Interp* interp;
  InterpState* state;
  Tcl_Obj* apply;
  Tcl_Obj* lambda;
  ExprFn(Tcl_Interp* i, InterpState* s, const std::string& expr) : interp(i), state(s) {
    apply = Tcl_NewStringObj("::apply", -1);
    Tcl_IncrRefCount(apply);
    std::string l = "t {expr {" + expr + "}}";
    lambda = Tcl_NewStringObj(l.c_str(), int(l.size()));
    Tcl_IncrRefCount(lambda);
  }
  ~ExprFn() {
    Tcl_DecrRefCount(apply);
    Tcl_DecrRefCount(lambda);
  }
  // Returns the value at t, or false with the message in err.
  bool eval(double t, double& out, std::string& err) {
    Tcl_Obj* objv[3] = {apply, lambda, Tcl_NewDoubleObj(t)};
    Tcl_IncrRefCount(objv[2]);
    Tcl_InterpState saved = Tcl_SaveInterpState(interp, TCL_OK);
    int code = Tcl_EvalObjv(interp, 3, objv, TCL_EVAL_GLOBAL);
    bool ok =
        code == TCL_OK && Tcl_GetDoubleFromObj(nullptr, Tcl_GetObjResult(interp), &out) == TCL_OK;
    if (!ok)
      err = code == TCL_OK ? "expected a number but got \"" +
                                 std::string(Tcl_GetString(Tcl_GetObjResult(interp))) + "\""
                           : std::string(Tcl_GetString(Tcl_GetObjResult(interp)));
    Tcl_DecrRefCount(objv[2]);
    Tcl_RestoreInterpState(interp, saved);
    return ok;
  }
};

void setupSession(Tcl_Interp* interp, InterpState* st) {
  cmd::Session& s = st->session;
  // Under mpirun the terminal, if any, is mpirun's, which forwards the ranks' output in pieces:
  // no progress bar there.
  s.terminal = isatty(1) != 0 && !mpi::launched();
  // Through the puts command, not the channel, so whatever redirects puts (tcltest's -output,
  // a console widget) sees the report and the progress bar too.
  s.write = [interp](std::string_view text) {
    Tcl_Obj* objv[4] = {Tcl_NewStringObj("::puts", -1), Tcl_NewStringObj("-nonewline", -1),
                        Tcl_NewStringObj("stdout", -1),
                        Tcl_NewStringObj(text.data(), int(text.size()))};
    Tcl_Obj* flush[2] = {Tcl_NewStringObj("::flush", -1), Tcl_NewStringObj("stdout", -1)};
    for (Tcl_Obj* o : objv) Tcl_IncrRefCount(o);
    for (Tcl_Obj* o : flush) Tcl_IncrRefCount(o);
    Tcl_InterpState saved = Tcl_SaveInterpState(interp, TCL_OK);
    Tcl_EvalObjv(interp, 4, objv, TCL_EVAL_GLOBAL);
    Tcl_EvalObjv(interp, 2, flush, TCL_EVAL_GLOBAL);
    Tcl_RestoreInterpState(interp, saved);
    for (Tcl_Obj* o : objv) Tcl_DecrRefCount(o);
    for (Tcl_Obj* o : flush) Tcl_DecrRefCount(o);
  };
  s.beginRun = [st] {
    st->session.running = true;
    beginRun(&st->session.stop);
  };
  s.endRun = [st] {
    endRun();
    st->session.running = false;
  };
  s.catchSigint = [st] { beginRun(&st->session.stop); };
  s.releaseSigint = [] { endRun(); };
  s.evalScript = [interp](const std::string& script) {
    cmd::Session::ScriptResult r;
    Tcl_Obj* o = Tcl_NewStringObj(script.c_str(), int(script.size()));
    Tcl_IncrRefCount(o);
    int code = Tcl_EvalObjEx(interp, o, 0);
    Tcl_DecrRefCount(o);
    r.ok = code == TCL_OK || code == TCL_RETURN;
    r.result = Tcl_GetString(Tcl_GetObjResult(interp));
    if (code == TCL_BREAK || code == TCL_CONTINUE) {
      r.result = std::string("invoked \"") + (code == TCL_BREAK ? "break" : "continue") +
                 "\" outside of a loop";
    } else if (code == TCL_ERROR) {
      Tcl_Obj* opts = Tcl_GetReturnOptions(interp, code);
      Tcl_IncrRefCount(opts);
      Tcl_Obj* key = Tcl_NewStringObj("-errorcode", -1);
      Tcl_IncrRefCount(key);
      Tcl_Obj* ec = nullptr;
      int n = 0;
      Tcl_Obj** elems = nullptr;
      if (Tcl_DictObjGet(nullptr, opts, key, &ec) == TCL_OK && ec &&
          Tcl_ListObjGetElements(nullptr, ec, &n, &elems) == TCL_OK) {
        for (int k = 0; k < n; ++k) r.errorCode.emplace_back(Tcl_GetString(elems[k]));
      }
      Tcl_DecrRefCount(key);
      Tcl_DecrRefCount(opts);
    }
    Tcl_ResetResult(interp);
    return r;
  };
  s.timeFunction = [interp, st](const std::string& expr, const std::string& what, double t0,
                                const cmd::TimeBound& bound, double* first) -> sim::TimeFunction {
    auto fn = std::make_shared<ExprFn>(interp, st, expr);
    double v;
    std::string err;
    if (!fn->eval(t0, v, err)) {
      throw Error("bad " + what + " expression \"" + expr + "\": " + err,
                  {"VALUE", cmd::codeWord(what)});
    }
    if (!(std::abs(v) <= bound.limit)) {
      throw Error("bad " + what + " expression \"" + expr + "\": it gives " +
                      physics::formatReal(v) + " at t = " + physics::formatReal(t0) +
                      ", beyond " + bound.bound + " " + physics::formatReal(bound.limit),
                  {"VALUE", cmd::codeWord(what)});
    }
    if (first) *first = v;
    return [fn, bound](double t) {
      double out = 0;
      std::string err;
      // The constants' bound (core/validity.hpp) holds for values of scripts too.
      const bool ok = fn->eval(t, out, err);
      if (!ok || !(std::abs(out) <= bound.limit)) {
        if (fn->state->session.callbackError.empty()) {
          fn->state->session.callbackError =
              !ok ? err
                  : "a " + bound.noun + " expression gave " + physics::formatReal(out) +
                        ", beyond " + bound.bound + " " + physics::formatReal(bound.limit);
        }
        fn->state->session.stop = true;
        return 0.0;
      }
      return out;
    };
  };
}

// The half-made results of conversions Ctrl-C stopped, freed a slice at a time: freeing a list
// of 300 000 small lists at once took a quarter of a second, which the stopped command would
// spend before it returns. Tcl objects belong to their thread, so the lists wait in this
// thread's queue; each demlab command frees a few slices before it starts, and an idle
// handler (the console's event loop, `update`) frees the rest.
thread_local std::vector<Tcl_Obj*> t_halfMade;
constexpr int kFreeSlice = 1024;  // elements of a list freed at once: about a millisecond

// Frees up to kFreeSlice elements of the last queued list (the list itself once empty).
// Returns true while some remain queued.
bool freeHalfMadeSlice() {
  if (t_halfMade.empty()) return false;
  Tcl_Obj* list = t_halfMade.back();
  int n = 0;
  Tcl_ListObjLength(nullptr, list, &n);
  const int k = std::min(n, kFreeSlice);
  if (k > 0) Tcl_ListObjReplace(nullptr, list, n - k, k, 0, nullptr);
  if (n - k == 0) {
    Tcl_DecrRefCount(list);
    t_halfMade.pop_back();
  }
  return !t_halfMade.empty();
}

extern "C" void freeHalfMadeWhenIdle(ClientData) {
  if (freeHalfMadeSlice()) Tcl_DoWhenIdle(freeHalfMadeWhenIdle, nullptr);
}

// Queues list (holding one reference, which the queue takes) to be freed a slice at a time.
void freeLater(Tcl_Obj* list) {
  if (t_halfMade.empty()) Tcl_DoWhenIdle(freeHalfMadeWhenIdle, nullptr);
  t_halfMade.push_back(list);
}

extern "C" int dispatch(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  Bound* b = static_cast<Bound*>(cd);
  InterpState* st = stateOf(interp);
  for (int k = 0; k < 4 && freeHalfMadeSlice(); ++k) {
  }
  if (!st)
    return fail(interp, "demlab is not initialised in this interpreter", {"DEMLAB", "STATE"});
  std::vector<std::string> words;
  words.reserve(std::size_t(objc));
  words.push_back(b->word);
  for (int k = 1; k < objc; ++k) {
    int len;
    const char* s = Tcl_GetStringFromObj(objv[k], &len);
    words.emplace_back(s, std::size_t(len));
  }
  try {
    // The viewer's commands only read the scene and draw: its window redraws during runs.
    if (st->session.running && b->word != "help" && b->word != "query" && b->word != "viewer") {
      // A load expression calling back into demlab while the scene is stepping.
      throw Error("can't use \"" + b->word + "\" while the scene is running", {"STATE", "RUNNING"});
    }
    Tcl_Obj* result = nullptr;
    cmd::commandRegistry().invoke(words, st->session, [&](cmd::Value&& v, bool interruptible) {
      if (!interruptible) {
        result = toObj(v);
        return;
      }
      // Stopped while it is converted, a result of a million dicts is freed on a thread of its
      // own (plain C++ memory); the half-made Tcl objects are freed here.
      cmd::Value held = std::move(v);
      const FreeAsideOnThrow aside(held);
      InterruptPoll poll("query");
      result = toObj(held, &poll);
    });
    Tcl_SetObjResult(interp, result);
    return TCL_OK;
  } catch (const Error& e) {
    return fail(interp, e.what(), e.code());
  } catch (const std::bad_alloc&) {
    return fail(interp, "not enough memory", {"DEMLAB", "MEMORY"});
  } catch (const std::exception& e) {
    return fail(interp, std::string("internal error: ") + e.what(), {"DEMLAB", "INTERNAL"});
  } catch (...) {
    return fail(interp, "internal error", {"DEMLAB", "INTERNAL"});
  }
}

bool tclSplit(std::string_view text, std::vector<std::string>& out, std::string& error) {
  Tcl_Obj* o = Tcl_NewStringObj(text.data(), int(text.size()));
  Tcl_IncrRefCount(o);
  int n = 0;
  Tcl_Obj** elems = nullptr;
  bool ok = Tcl_ListObjGetElements(nullptr, o, &n, &elems) == TCL_OK;
  if (ok) {
    for (int k = 0; k < n; ++k) {
      int len;
      const char* s = Tcl_GetStringFromObj(elems[k], &len);
      out.emplace_back(s, std::size_t(len));
    }
  } else {
    // Tcl gives no message without an interpreter; the built-in splitter words it the same way.
    cmd::setListSplitter(nullptr);
    try {
      cmd::splitList(text);
      error = "malformed list";
    } catch (const Error& e) {
      error = e.what();
    }
    cmd::setListSplitter(tclSplit);
  }
  Tcl_DecrRefCount(o);
  return ok;
}

}  // namespace

cmd::Session* sessionOf(Tcl_Interp* interp) {
  InterpState* st = stateOf(interp);
  return st ? &st->session : nullptr;
}

namespace {

// Returns o, holding one reference less, without freeing it at zero: an object built with a
// reference held (so that an interrupt part way frees it with what it holds) is handed to its
// caller with refcount 0, as Tcl_New*Obj would.
Tcl_Obj* disown(Tcl_Obj* o) {
  o->refCount -= 1;
  return o;
}

// Returns a new list (refcount 0) of the n objects make(k) returns, calling poll (when given)
// before each. Throws what poll or make throws, having freed what it made.
template <class Make>
Tcl_Obj* listOf(std::size_t n, InterruptPoll* poll, const Make& make) {
  Tcl_Obj* o = Tcl_NewListObj(0, nullptr);
  Tcl_IncrRefCount(o);
  try {
    for (std::size_t k = 0; k < n; ++k) {
      if (poll) (*poll)();
      Tcl_ListObjAppendElement(nullptr, o, make(k));
    }
  } catch (...) {
    if (poll) {  // stopped: freed later, a slice at a time
      freeLater(o);
    } else {
      Tcl_DecrRefCount(o);
    }
    throw;
  }
  return disown(o);
}

}  // namespace

Tcl_Obj* toObj(cmd::Value& v, InterruptPoll* poll) {
  // The dict keys of one result, one object each however many dicts use it (a list of a million
  // contacts repeats eight keys), each holding a reference of the cache's until the end.
  struct Keys {
    std::vector<std::pair<std::string_view, Tcl_Obj*>> objs;
    ~Keys() {
      for (auto& [k, o] : objs) Tcl_DecrRefCount(o);
    }
    Tcl_Obj* get(const std::string& key) {
      for (auto& [k, o] : objs)
        if (k == key) return o;
      Tcl_Obj* o = Tcl_NewStringObj(key.c_str(), int(key.size()));
      Tcl_IncrRefCount(o);
      objs.emplace_back(key, o);
      return o;
    }
  } keys;
  struct Visitor {
    InterruptPoll* poll;
    Keys& keys;
    Tcl_Obj* of(cmd::Value& e) const { return std::visit(*this, e.v); }
    Tcl_Obj* operator()(std::monostate) const { return Tcl_NewObj(); }
    Tcl_Obj* operator()(bool b) const { return Tcl_NewBooleanObj(b); }
    Tcl_Obj* operator()(std::int64_t i) const { return Tcl_NewWideIntObj(Tcl_WideInt(i)); }
    Tcl_Obj* operator()(double d) const { return Tcl_NewDoubleObj(d); }
    Tcl_Obj* operator()(const std::string& s) const {
      return Tcl_NewStringObj(s.c_str(), int(s.size()));
    }
    Tcl_Obj* operator()(cmd::List& l) const {
      return listOf(l.size(), poll, [&](std::size_t k) { return of(l[k]); });
    }
    // A dict is made as the list of its keys and values (Tcl makes the hash table when a
    // script first reads it as a dict): a list of a million small dicts is made and freed in a
    // fraction of the time, so Ctrl-C also returns sooner from one half made.
    Tcl_Obj* operator()(cmd::Dict& d) const {
      return listOf(2 * d.size(), nullptr, [&](std::size_t k) {
        return k % 2 == 0 ? keys.get(d[k / 2].first) : of(d[k / 2].second);
      });
    }
    // Many ids (a packing's, bond add's) are taken over, not copied, as one value that becomes
    // a Tcl list when a script reads it (tcl/int_list_obj.hpp); a few are a list at once.
    Tcl_Obj* operator()(cmd::Ints& l) const {
      const std::size_t n = l.data.size();
      if (n >= kLazyIntList && n <= kMaxIntListObj) return newIntListObj(std::move(l.data));
      return listOf(n, poll, [&](std::size_t k) { return Tcl_NewWideIntObj(Tcl_WideInt(l.data[k])); });
    }
    Tcl_Obj* operator()(const cmd::Bytes& b) const {
      return Tcl_NewByteArrayObj(b.data.data(), int(b.data.size()));
    }
    Tcl_Obj* operator()(const cmd::Reals& r) const {
      const std::size_t n = r.data.size();
      if (r.stride <= 0)
        return listOf(n, poll, [&](std::size_t k) { return Tcl_NewDoubleObj(r.data[k]); });
      const std::size_t m = std::size_t(r.stride);
      std::vector<Tcl_Obj*> tuple(m);
      return listOf(n / m, poll, [&](std::size_t k) {
        for (std::size_t j = 0; j < m; ++j) tuple[j] = Tcl_NewDoubleObj(r.data[k * m + j]);
        return Tcl_NewListObj(int(m), tuple.data());
      });
    }
  };
  // The result is never a key itself (keys only go into dicts), so the cache's references can
  // go as it goes: the keys the result holds stay.
  return Visitor{poll, keys}.of(v);
}

std::vector<std::string> completions(Tcl_Interp* interp, const std::string& line,
                                     std::string& partial) {
  // The words of the last command on the line: after the last unbracketed ;, newline or [.
  std::size_t start = 0;
  for (std::size_t k = 0; k < line.size(); ++k)
    if (line[k] == ';' || line[k] == '\n' || line[k] == '[') start = k + 1;
  std::string cmdText = line.substr(start);
  std::vector<std::string> words;
  std::string cur;
  for (char c : cmdText) {
    if (c == ' ' || c == '\t') {
      if (!cur.empty()) words.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  partial = cur;
  std::vector<std::string> out;
  InterpState* st = stateOf(interp);
  if (!st) return out;
  out = cmd::commandRegistry().complete(words, partial, st->session);
  if (words.empty()) {
    // Any other Tcl command too (puts, proc, ...).
    std::string script = "lsort [info commands {" + partial + "*}]";
    if (partial.find_first_of("{}\\[]$\" ") == std::string::npos &&
        Tcl_EvalEx(interp, script.c_str(), -1, TCL_EVAL_GLOBAL) == TCL_OK) {
      int n;
      Tcl_Obj** elems;
      if (Tcl_ListObjGetElements(nullptr, Tcl_GetObjResult(interp), &n, &elems) == TCL_OK) {
        for (int k = 0; k < n; ++k) {
          std::string w = Tcl_GetString(elems[k]);
          if (std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
        }
      }
    }
    Tcl_ResetResult(interp);
    std::sort(out.begin(), out.end());
  }
  return out;
}

}  // namespace demlab::tcl

using namespace demlab;

namespace {

// Tcl's exit handler: lets work that stopped commands left running finish before the process
// exits (Tcl runs it before exit(), so before the C libraries' own exit handlers).
extern "C" void awaitBackgroundWorkAtExit(ClientData) {
  awaitBackgroundWork(10.0);
}

}  // namespace

extern "C" int Demlab_Init(Tcl_Interp* interp) {
  if (!Tcl_InitStubs(interp, "8.6", 0)) return TCL_ERROR;
  if (tcl::stateOf(interp)) return Tcl_PkgProvide(interp, "demlab", DEMLAB_PKG_VERSION);
  static const bool exitHandled = [] {
    Tcl_CreateExitHandler(awaitBackgroundWorkAtExit, nullptr);
    return true;
  }();
  (void)exitHandled;
  cmd::setListSplitter(tcl::tclSplit);
  auto* st = new tcl::InterpState;
  st->interp = interp;
  Tcl_SetAssocData(interp, tcl::kAssocKey, tcl::deleteState, st);
  tcl::setupSession(interp, st);
  // The commands live in ::demlab and are exported, so loading the package replaces no
  // command of the interpreter's (Tk's pack, a user's proc); `namespace import demlab::*`
  // brings them in, and the ensemble ::demlab (when no command of that name exists) reaches
  // them as `demlab sim new`.
  std::string exports;
  try {
    for (const std::string& w : cmd::commandRegistry().topWords()) {
      std::string name = "::demlab::" + w;
      Tcl_CreateObjCommand(interp, name.c_str(), tcl::dispatch, new tcl::Bound{&st->session, w},
                           tcl::deleteBound);
      exports += " " + w;
    }
  } catch (const std::exception& e) {
    return tcl::fail(interp, std::string("demlab: ") + e.what(), {"DEMLAB", "INTERNAL"});
  }
  if (Tcl_EvalEx(interp, demlabTclLibrary, -1, TCL_EVAL_GLOBAL) != TCL_OK) return TCL_ERROR;
  const std::string setup = "namespace eval ::demlab {namespace export" + exports +
                            "}\n"
                            "if {[info commands ::demlab] eq {}} {"
                            "namespace eval ::demlab {namespace ensemble create}}";
  if (Tcl_EvalEx(interp, setup.c_str(), -1, TCL_EVAL_GLOBAL) != TCL_OK) return TCL_ERROR;
  return Tcl_PkgProvide(interp, "demlab", DEMLAB_PKG_VERSION);
}

std::string demlab::tcl::helpersMarkdown() {
  // The exported helpers' names come from the library's `namespace export` line; each one's
  // text is the comment block above its proc: a usage line, then the description.
  const std::string lib = demlabTclLibrary;
  std::vector<std::string> names;
  {
    const size_t at = lib.find("namespace export ");
    const size_t end = lib.find('\n', at);
    std::string list = lib.substr(at + 17, end - at - 17);
    size_t k = 0;
    while (k < list.size()) {
      const size_t sp = list.find(' ', k);
      const std::string w = list.substr(k, sp == std::string::npos ? std::string::npos : sp - k);
      if (!w.empty()) names.push_back(w);
      if (sp == std::string::npos) break;
      k = sp + 1;
    }
  }
  std::string out =
      "\n## Tcl helpers (`tcl/demlab.tcl`)\n\nProcedures written in Tcl over the commands, in "
      "the namespace `demlab` (exported: `namespace import demlab::*` brings them in with the "
      "commands). Their text is the comment above each procedure.\n";
  for (const std::string& name : names) {
    const std::string head = "\n# demlab::" + name;
    const size_t at = lib.find(head);
    const size_t proc = lib.find("\nproc ::demlab::" + name + " ", at);
    if (at == std::string::npos || proc == std::string::npos) continue;
    std::string usage, text;
    size_t line = at + 1;
    while (line < proc) {
      const size_t end = lib.find('\n', line);
      std::string l = lib.substr(line, end - line);
      l = l.size() > 2 ? l.substr(2) : "";
      if (usage.empty()) {
        usage = l;
      } else if (text.empty() && !l.empty() && l[0] == ' ') {  // the usage line continued
        usage += " " + l.substr(l.find_first_not_of(' '));
      } else {
        text += (text.empty() ? "" : " ") + l;
      }
      line = end + 1;
    }
    out += "\n### `" + usage + "`\n\n" + text + "\n";
  }
  return out;
}

extern "C" int Demlab_ImportCommands(Tcl_Interp* interp) {
  // Only the commands, not the helper procedures (demlab::settle, ...), which keep their
  // namespace in the console as in a script that loads the package.
  std::string script = "namespace eval :: {namespace import";
  for (const std::string& w : cmd::commandRegistry().topWords()) script += " ::demlab::" + w;
  script += "}";
  if (Tcl_EvalEx(interp, script.c_str(), -1, TCL_EVAL_GLOBAL) != TCL_OK) return TCL_ERROR;
  // Tk (loaded by `viewer open`, or by the user) replaces the imported `pack` with its own
  // geometry manager. The two share no subcommand, and Tk's takes a window path or one of its
  // own words first: after any `load`, a Tk pack found at ::pack is moved aside and ::pack
  // sends each call to the one it is for, so `pack lattice` and Tk's `pack .b` both work.
  static const char* const mergePack = R"TCL(
proc ::demlab::MergePack {args} {
    if {[info commands ::pack] eq "" || [namespace origin ::pack] eq "::demlab::pack"
        || [info commands ::demlab::TkPack] ne ""} return
    rename ::pack ::demlab::TkPack
    proc ::pack {args} {
        set first [lindex $args 0]
        if {[string index $first 0] eq "." ||
            $first in {configure content forget info propagate slaves}} {
            tailcall ::demlab::TkPack {*}$args
        }
        tailcall ::demlab::pack {*}$args
    }
}
trace add execution ::load leave ::demlab::MergePack
)TCL";
  return Tcl_EvalEx(interp, mergePack, -1, TCL_EVAL_GLOBAL);
}
