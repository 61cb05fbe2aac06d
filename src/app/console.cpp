#include "app/console.hpp"

#include <histedit.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "tcl/binding.hpp"

namespace demlab::app {

namespace {

struct ConsoleState {
  Tcl_Interp* interp;
  bool continuation = false;
};

ConsoleState* g_console = nullptr;

char* prompt(EditLine*) {
  static char primary[] = "demlab% ";
  static char secondary[] = "> ";
  return g_console && g_console->continuation ? secondary : primary;
}

// Tab: completes the word before the cursor from the command declarations; several candidates
// are completed to their common prefix, then listed.
unsigned char complete(EditLine* el, int) {
  const LineInfo* li = el_line(el);
  std::string line(li->buffer, std::size_t(li->cursor - li->buffer));
  std::string partial;
  std::vector<std::string> c = tcl::completions(g_console->interp, line, partial);
  if (c.empty()) return CC_ERROR;
  std::string common = c[0];
  for (const std::string& w : c) {
    std::size_t k = 0;
    while (k < common.size() && k < w.size() && common[k] == w[k]) ++k;
    common.resize(k);
  }
  if (common.size() > partial.size()) {
    std::string add = common.substr(partial.size());
    if (c.size() == 1) add += ' ';
    el_insertstr(el, add.c_str());
    return CC_REFRESH;
  }
  if (c.size() == 1) {
    el_insertstr(el, " ");
    return CC_REFRESH;
  }
  std::string list = "\n";
  for (const std::string& w : c) list += w + "  ";
  list += "\n";
  std::fputs(list.c_str(), stdout);
  std::fflush(stdout);
  return CC_REDISPLAY;
}

bool g_cancelLine = false;

// Ctrl-C at the prompt (a key here, not a signal: ISIG is off while editing): drops the input.
unsigned char cancelLine(EditLine*, int) {
  g_cancelLine = true;
  std::fputs("^C\n", stdout);
  std::fflush(stdout);
  return CC_NEWLINE;
}

void printResult(Tcl_Interp* interp, int code) {
  const char* r = Tcl_GetStringResult(interp);
  if (code == TCL_OK) {
    if (*r) std::printf("%s\n", r);
  } else {
    std::fprintf(stderr, "%s\n", r);
  }
  std::fflush(stdout);
  std::fflush(stderr);
}

}  // namespace

int evaluate(Tcl_Interp* interp, const char* script) {
  tcl::setEvaluating(true);
  int code = Tcl_EvalEx(interp, script, -1, TCL_EVAL_GLOBAL);
  // A Ctrl-C that came too late to stop anything is dropped, not kept for the next command.
  code = Tcl_AsyncReady() ? Tcl_AsyncInvoke(interp, code) : code;
  tcl::setEvaluating(false);
  return code;
}

int runConsole(Tcl_Interp* interp, const char* argv0) {
  ConsoleState state{interp};
  g_console = &state;
  EditLine* el = el_init(argv0, stdin, stdout, stderr);
  History* hist = history_init();
  HistEvent ev;
  history(hist, &ev, H_SETSIZE, 2000);
  history(hist, &ev, H_SETUNIQUE, 1);
  std::string histFile;
  if (const char* home = std::getenv("HOME")) {
    histFile = std::string(home) + "/.demlab_history";
    history(hist, &ev, H_LOAD, histFile.c_str());
  }
  el_set(el, EL_EDITOR, "emacs");
  el_set(el, EL_PROMPT, prompt);
  el_set(el, EL_HIST, history, hist);
  el_set(el, EL_ADDFN, "demlab-complete", "complete a command, option or value", complete);
  el_set(el, EL_BIND, "^I", "demlab-complete", nullptr);
  el_set(el, EL_SETTY, "-d", "-isig", nullptr);
  el_set(el, EL_ADDFN, "demlab-cancel", "drop the input", cancelLine);
  el_set(el, EL_BIND, "^C", "demlab-cancel", nullptr);
  el_source(el, nullptr);  // ~/.editrc
  // Tcl gives terminal channels "-translation crlf" (for raw-mode ttys); commands run with the
  // terminal cooked, where the tty's own onlcr already makes \n a line end, so crlf printed
  // every line of `puts` as "\r\r\n".
  for (int which : {TCL_STDOUT, TCL_STDERR})
    if (Tcl_Channel ch = Tcl_GetStdChannel(which))
      Tcl_SetChannelOption(nullptr, ch, "-translation", "lf");

  std::printf("demlab %s: type help for the commands, exit or Ctrl-D to leave\n",
              Tcl_GetVar(interp, "::demlab::version", TCL_GLOBAL_ONLY)
                  ? Tcl_GetVar(interp, "::demlab::version", TCL_GLOBAL_ONLY)
                  : "");
  std::string buffer;
  while (true) {
    state.continuation = !buffer.empty();
    int count = 0;
    errno = 0;
    const char* line = el_gets(el, &count);
    if (g_cancelLine || tcl::takePromptInterrupt()) {
      // Ctrl-C at the prompt: drop what was typed and start again.
      g_cancelLine = false;
      buffer.clear();
      continue;
    }
    if (!line || count <= 0) {
      if (errno == EINTR) continue;
      std::printf("\n");
      break;
    }
    buffer += line;
    if (!Tcl_CommandComplete(buffer.c_str())) continue;
    std::string command = buffer;
    buffer.clear();
    std::string entry = command;
    while (!entry.empty() && entry.back() == '\n') entry.pop_back();
    if (entry.empty()) continue;
    history(hist, &ev, H_ENTER, entry.c_str());
    int code = evaluate(interp, command.c_str());
    printResult(interp, code);
  }
  if (!histFile.empty()) history(hist, &ev, H_SAVE, histFile.c_str());
  history_end(hist);
  el_end(el);
  g_console = nullptr;
  return 0;
}

int runStdin(Tcl_Interp* interp) {
  std::string buffer, line;
  int status = 0;
  while (std::getline(std::cin, line)) {
    buffer += line;
    buffer += '\n';
    if (!Tcl_CommandComplete(buffer.c_str())) continue;
    int code = evaluate(interp, buffer.c_str());
    buffer.clear();
    if (code != TCL_OK) {
      printResult(interp, code);
      status = 1;
    }
  }
  if (!buffer.empty()) {
    std::fprintf(stderr, "incomplete command at end of input\n");
    status = 1;
  }
  return status;
}

}  // namespace demlab::app
