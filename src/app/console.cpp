#include "app/console.hpp"

#include <histedit.h>
#include <poll.h>
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
    // A folder is completed to its "/", ready for what is inside it.
    if (c.size() == 1 && c[0].back() != '/') add += ' ';
    el_insertstr(el, add.c_str());
    return CC_REFRESH;
  }
  if (c.size() == 1 && c[0].back() != '/') {
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

// Returns 1 and the next byte of the console's input in *b (a Ctrl-C key, 0x03, when a SIGINT
// met the prompt), 0 at end of input, or -1 on an error. libedit's own reader blocks in
// read(): a SIGINT that arrives after the prompt is printed but before libedit puts the
// terminal in raw mode (so ^C is still a signal, not a key) and before read() starts would
// leave the console waiting with no new prompt. Waiting on the interrupt's wake-up pipe as
// well closes that gap; the signal becomes the key, so both take the same path (cancelLine).
//
// While it waits, Tcl's events are served every 20 ms, as tclsh serves them at its prompt: a
// viewer window (Tk) stays live, and `after` scripts run.
int readByte(unsigned char* b) {
  while (true) {
    pollfd fds[2] = {{STDIN_FILENO, POLLIN, 0}, {tcl::promptWakeFd(), POLLIN, 0}};
    const int ready = poll(fds, fds[1].fd >= 0 ? 2 : 1, 20);
    if (ready < 0) {
      if (errno == EINTR) continue;  // the handler wrote the pipe if it was for the prompt
      return -1;
    }
    if (ready == 0) {
      while (Tcl_DoOneEvent(TCL_ALL_EVENTS | TCL_DONT_WAIT)) {
      }
      continue;
    }
    if (fds[1].fd >= 0 && (fds[1].revents & POLLIN)) {
      tcl::takePromptInterrupt();  // clears the flag and drains the pipe
      *b = 0x03;
      return 1;
    }
    const ssize_t r = read(STDIN_FILENO, b, 1);
    if (r >= 0) return int(r);
    if (errno != EINTR && errno != EAGAIN) return -1;
  }
}

// Returns the length of the UTF-8 sequence that lead starts (1 for ASCII, and for a byte that
// starts none).
int sequenceLength(unsigned char lead) {
  if ((lead >> 5) == 0x6) return 2;
  if ((lead >> 4) == 0xe) return 3;
  if ((lead >> 3) == 0x1e) return 4;
  return 1;
}

// libedit's character reader (EL_GETCFN): returns 1 and the next character in *out, UTF-8
// decoded (a broken sequence gives its first byte as is), 0 at end of input, -1 on an error.
int readChar(EditLine*, wchar_t* out) {
  static int pending = -1;  // the byte that broke the last sequence: the next one's start
  unsigned char seq[4];
  if (pending >= 0) {
    seq[0] = static_cast<unsigned char>(pending);
    pending = -1;
  } else if (const int r = readByte(&seq[0]); r != 1) {
    return r;
  }
  const int need = sequenceLength(seq[0]);
  for (int have = 1; have < need; ++have) {
    if (const int r = readByte(&seq[have]); r != 1) return r;
    if ((seq[have] & 0xc0) != 0x80) {
      pending = seq[have];
      *out = wchar_t(seq[0]);
      return 1;
    }
  }
  unsigned cp = need == 1 ? seq[0] : seq[0] & (0x7f >> need);
  for (int k = 1; k < need; ++k) cp = (cp << 6) | (seq[k] & 0x3f);
  *out = wchar_t(cp);
  return 1;
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
  el_set(el, EL_GETCFN, readChar);
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
      // Ctrl-C at the prompt (the key, or a signal readByte turned into it): drop what was
      // typed and start again.
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
    // Saved before it runs: `exit`, a kill or a crash ends the session without the loop's end.
    // Written beside the file and renamed over it, so the file is never seen half written.
    if (!histFile.empty()) {
      const std::string tmp = histFile + ".tmp" + std::to_string(getpid());
      if (history(hist, &ev, H_SAVE, tmp.c_str()) >= 0) {
        std::rename(tmp.c_str(), histFile.c_str());
      } else {
        std::remove(tmp.c_str());
      }
    }
    int code = evaluate(interp, command.c_str());
    printResult(interp, code);
  }
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
