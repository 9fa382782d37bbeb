// `asimov monitor` (and `asimov` alone): the VAL monitor of dialect §9 over the interpreter,
// robot and cell of `asimov run`. Interactive when stdin is a terminal (libedit: prompt ". ",
// history in ~/.asimov_history, tab completion, Ctrl-C); otherwise commands are read line by
// line with no prompt, so sessions can be piped in.
#include "asimov/cell/cell_loader.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/sigint.hpp"
#include "asimov/interpreter/monitor.hpp"

#include <fmt/format.h>
#include <histedit.h>

#include <cerrno>
#include <cstdlib>
#include <cwchar>
#include <filesystem>
#include <iostream>
#include <streambuf>
#include <poll.h>
#include <unistd.h>

namespace asimov::app {
namespace {

// stdin one byte at a time, as libedit reads it: PROMPT replies and Y/N answers read through
// it never swallow a command typed ahead.
class UnbufferedStdin : public std::streambuf {
 protected:
  int_type underflow() override {
    if (::read(STDIN_FILENO, &c_, 1) != 1) return traits_type::eof();
    setg(&c_, &c_, &c_ + 1);
    return traits_type::to_int_type(c_);
  }

 private:
  char c_ = 0;
};

std::string history_path() {
  const char* home = std::getenv("HOME");
  return home && *home ? std::string(home) + "/.asimov_history" : std::string();
}

// ". ", or while a program is typed after .PROGRAM the step number of the next line.
const char* prompt(EditLine* el) {
  static std::string text;
  void* data = nullptr;
  el_get(el, EL_CLIENTDATA, &data);
  const auto* monitor = static_cast<const interpreter::Monitor*>(data);
  if (!monitor || !monitor->entering_program()) return ". ";
  text = fmt::format("{:>4}  ", monitor->entry_step());
  return text.c_str();
}

// Reads one character for libedit. Ctrl-C at the prompt ends the line early; the caller sees
// the flag and drops what was typed.
// The flag is checked before each wait and at least every 100 ms, so a Ctrl-C that arrives
// outside the read itself is not lost.
int read_char(EditLine*, wchar_t* c) {
  for (;;) {
    if (sigint_flag().load()) {
      *c = L'\n';
      return 1;
    }
    pollfd p{STDIN_FILENO, POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);
    if (ready < 0 && errno != EINTR) return -1;
    if (ready <= 0) continue;
    char byte = 0;
    const ssize_t n = ::read(STDIN_FILENO, &byte, 1);
    if (n == 1) {
      *c = static_cast<unsigned char>(byte);
      return 1;
    }
    if (n == 0) return 0;
    if (errno != EINTR && errno != EAGAIN) return -1;
  }
}

// Tab: completes the word before the cursor from Monitor::completions; lists the candidates
// when there are several and no longer common prefix.
unsigned char complete(EditLine* el, int) {
  void* data = nullptr;
  el_get(el, EL_CLIENTDATA, &data);
  const auto* monitor = static_cast<const interpreter::Monitor*>(data);
  const LineInfo* li = el_line(el);
  const std::string line(li->buffer, li->cursor);
  std::size_t start = line.size();
  while (start > 0 && std::string_view(" \t,(=:").find(line[start - 1]) == std::string_view::npos) --start;
  const std::string word = line.substr(start);
  const std::vector<std::string> all = monitor->completions(line, word);
  if (all.empty()) return CC_ERROR;
  if (all.size() == 1) {
    const std::string rest = all[0].substr(word.size()) + " ";
    return el_insertstr(el, rest.c_str()) == 0 ? CC_REFRESH : CC_ERROR;
  }
  std::size_t common = all[0].size();  // longest common prefix, case-insensitive
  for (const auto& s : all) {
    std::size_t k = 0;
    while (k < common && k < s.size() && std::tolower(static_cast<unsigned char>(s[k])) ==
                                             std::tolower(static_cast<unsigned char>(all[0][k])))
      ++k;
    common = k;
  }
  if (common > word.size()) {
    const std::string rest = all[0].substr(word.size(), common - word.size());
    return el_insertstr(el, rest.c_str()) == 0 ? CC_REFRESH : CC_ERROR;
  }
  std::string list = "\n";
  for (const auto& s : all) list += s + "  ";
  std::cout << list << '\n' << std::flush;
  return CC_REDISPLAY;
}

// Y/N questions (interactive only). Read byte by byte, as libedit reads, so that no typed-ahead
// command is swallowed by a stream buffer.
bool ask(const std::string& question) {
  std::cout << question << std::flush;
  std::string answer;
  char c = 0;
  while (::read(STDIN_FILENO, &c, 1) == 1 && c != '\n')
    if (answer.size() < 16) answer += c;  // only the first letter counts
  return !answer.empty() && (answer[0] == 'y' || answer[0] == 'Y');
}

// Runs the monitor on lines from libedit until QUIT or Ctrl-D.
int interactive(interpreter::Monitor& monitor, bool strict) {
  EditLine* el = el_init("asimov", stdin, stdout, stderr);
  History* hist = history_init();
  HistEvent ev;
  history(hist, &ev, H_SETSIZE, 1000);
  history(hist, &ev, H_SETUNIQUE, 1);
  const std::string hist_file = history_path();
  if (!hist_file.empty()) history(hist, &ev, H_LOAD, hist_file.c_str());
  el_set(el, EL_EDITOR, "emacs");
  el_set(el, EL_PROMPT, prompt);
  el_set(el, EL_HIST, history, hist);
  el_set(el, EL_GETCFN, read_char);
  el_set(el, EL_CLIENTDATA, &monitor);
  el_set(el, EL_ADDFN, "asimov-complete", "complete a command or name", complete);
  el_set(el, EL_BIND, "^I", "asimov-complete", nullptr);
  el_source(el, nullptr);  // ~/.editrc, as other libedit programs do

  int rc = kExitCompleted;
  for (;;) {
    sigint_flag().store(false);
    int count = 0;
    const char* got = el_gets(el, &count);
    if (sigint_flag().load()) {  // Ctrl-C at the prompt: the line is dropped
      if (monitor.entering_program()) std::cout << "(the program being entered is kept; end it with .END)\n";
      continue;
    }
    if (!got || count <= 0) {  // Ctrl-D on an empty line
      std::cout << '\n';
      // While a program is typed, Ctrl-D ends it (as .END) and the monitor goes on; at the
      // ". " prompt it ends the session.
      if (monitor.entering_program()) {
        if (monitor.execute(".END") == interpreter::CommandStatus::failed && strict) {
          rc = kExitProgramError;
          break;
        }
        std::cout << std::flush;
        continue;
      }
      if (monitor.end_of_input() == interpreter::CommandStatus::failed && strict) rc = kExitProgramError;
      break;
    }
    std::string line(got);
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    if (!line.empty()) {
      history(hist, &ev, H_ENTER, line.c_str());
      if (!hist_file.empty()) history(hist, &ev, H_SAVE, hist_file.c_str());
    }
    const interpreter::CommandStatus s = monitor.execute(line);
    std::cout << std::flush;
    if (s == interpreter::CommandStatus::quit) break;
    if (s == interpreter::CommandStatus::failed && strict) {
      rc = kExitProgramError;
      break;
    }
  }
  history_end(hist);
  el_end(el);
  return rc;
}

// A monitor line (docs/limits.md): far above a typed command or program line, far below what
// exhausts memory (a 300 MB line took 2.6 GB and was echoed twice in its error).
constexpr std::size_t kMaxMonitorLine = 65536;

// One line of `in` without its end, at most kMaxMonitorLine bytes kept (a longer one is read to
// its end and `too_long` set); false at the end of input.
bool read_line(std::istream& in, std::string& line, bool& too_long) {
  line.clear();
  too_long = false;
  std::streambuf* buf = in.rdbuf();
  bool any = false;
  for (;;) {
    const int c = buf ? buf->sbumpc() : std::char_traits<char>::eof();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return any;
    }
    any = true;
    if (c == '\n') return true;
    if (line.size() < kMaxMonitorLine) line.push_back(static_cast<char>(c));
    else too_long = true;
  }
}

// Scripted mode: one command per line from stdin, no prompt, no confirmation.
int scripted(interpreter::Monitor& monitor, std::istream& in, std::ostream& out, bool strict) {
  std::string line;
  bool too_long = false;
  while (read_line(in, line, too_long)) {
    sigint_flag().store(false);
    if (too_long) {  // not run, not echoed: only its size is named
      out << fmt::format("*Line too long*  a monitor line is longer than {} bytes (docs/limits.md)\n", kMaxMonitorLine);
      out.flush();
      if (strict) return kExitProgramError;
      continue;
    }
    const interpreter::CommandStatus s = monitor.execute(line);
    out.flush();
    if (s == interpreter::CommandStatus::quit) break;
    if (s == interpreter::CommandStatus::failed && strict) return kExitProgramError;
  }
  if (monitor.end_of_input() == interpreter::CommandStatus::failed && strict) return kExitProgramError;
  out.flush();
  return kExitCompleted;
}

}  // namespace

int monitor_command(const MonitorOptions& opt, std::istream& in, std::ostream& out, std::ostream& err) {
  for (const std::string& f : opt.files)
    if (!require_file(f, err)) return kExitUsage;
  auto cell = cell::load_cell_for_command(opt.cell, err);
  if (!cell) return kExitUsage;
  motion::Simulator sim(std::move(*cell));
  interpreter::Interpreter interp(sim, out);
  interpreter::Monitor monitor(interp, sim, out);
  interp.limits().interrupt = &sigint_flag();
  const bool tty = ::isatty(STDIN_FILENO) == 1 && &in == &std::cin;
  UnbufferedStdin tty_buffer;
  std::istream tty_in(&tty_buffer);
  interp.set_input(tty ? tty_in : in, tty);  // PROMPT reads the next line of the session
  if (tty) {
    monitor.confirm = ask;
    install_sigint(false);  // scripted sessions keep the default: Ctrl-C ends them
  }

  for (const std::string& f : opt.files)  // as LOAD f
    if (monitor.execute("LOAD " + f) == interpreter::CommandStatus::failed && opt.strict) return kExitProgramError;
  return tty ? interactive(monitor, opt.strict) : scripted(monitor, in, out, opt.strict);
}

}  // namespace asimov::app
