// The interactive monitor in a real pseudo-terminal (forkpty): prompt, tab completion,
// history (Ctrl-P, kept in ~/.asimov_history across sessions), Ctrl-C at the prompt and while
// a program runs, the ZERO confirmation, Ctrl-D.
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <poll.h>
#include <pty.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

// One `asimov monitor` on the slave side of a pty, in `dir`, with HOME = `home`.
class PtySession {
 public:
  PtySession(const fs::path& dir, const fs::path& home) {
    winsize ws{};
    ws.ws_row = 40;
    ws.ws_col = 120;
    pid_ = ::forkpty(&fd_, nullptr, nullptr, &ws);
    if (pid_ == 0) {
      if (::chdir(dir.c_str()) != 0) ::_exit(126);
      ::setenv("HOME", home.c_str(), 1);
      ::setenv("TERM", "xterm", 1);
      ::execl(ASIMOV_BINARY, "asimov", "monitor", static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~PtySession() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    if (fd_ >= 0) ::close(fd_);
  }
  bool started() const { return pid_ > 0 && fd_ >= 0; }

  void send(const std::string& keys) {
    const ssize_t n = ::write(fd_, keys.data(), keys.size());
    (void)n;
  }

  // Reads until `text` appears after the previous match (or the timeout); moves past it.
  bool expect(const std::string& text, double timeout_s = 10) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
      if (const auto at = seen_.find(text, mark_); at != std::string::npos) {
        mark_ = at + text.size();
        return true;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || !read_some(static_cast<int>(left.count()))) return false;
    }
  }

  // Exit code after end of input; 1000 + signal when killed; -1 while still running.
  int wait_exit(double timeout_s = 10) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      read_some(50);
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);  // killed: 1000 + signal
      }
    }
    return -1;
  }

  const std::string& seen() const { return seen_; }
  std::string since_mark() const { return seen_.substr(mark_); }

 private:
  bool read_some(int timeout_ms) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
    char buf[4096];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n <= 0) return false;
    seen_.append(buf, static_cast<std::size_t>(n));
    return true;
  }

  int fd_ = -1;
  pid_t pid_ = -1;
  bool exited_ = false;
  std::string seen_;
  std::size_t mark_ = 0;
};

}  // namespace

TEST_CASE("interactive monitor in a pty: completion, history, Ctrl-C, confirmation, Ctrl-D", "[monitor][pty]") {
  const fs::path dir = asimov::test::scratch_dir() / "pty";
  fs::remove_all(dir);
  fs::create_directories(dir / "home");
  fs::copy_file(asimov::test::source_path("programs/monitor/square.v2"), dir / "square.v2");
  {
    PtySession s(dir, dir / "home");
    REQUIRE(s.started());
    REQUIRE(s.expect(". "));  // the prompt

    s.send("LOAD square\r");
    REQUIRE(s.expect(". "));

    // Tab completes a unique prefix of a command, and of a program name.
    s.send("WH\t");  // the line becomes WHERE (libedit may redraw only the new part)
    REQUIRE(s.expect("ERE "));
    s.send("\r");
    REQUIRE(s.expect("         J1"));
    REQUIRE(s.expect(". "));
    s.send("EXECUTE tw\t");
    REQUIRE(s.expect("ice "));
    s.send("\r");
    REQUIRE(s.expect("Program completed: twice"));

    // Ctrl-P recalls the previous line (history).
    REQUIRE(s.expect(". "));
    s.send("\x10\r");
    REQUIRE(s.expect("Program completed: twice"));

    // Ctrl-C at the prompt drops the line being typed.
    REQUIRE(s.expect(". "));
    s.send("garbage");
    REQUIRE(s.expect("garbage"));
    s.send("\x03");
    INFO(s.since_mark());
    REQUIRE(s.expect(". "));  // a fresh prompt (the tty flushes input sent with the signal)
    s.send("DIRECTORY\r");
    REQUIRE(s.expect("square(a, $label)"));
    CHECK(s.seen().find("*Unknown command*") == std::string::npos);

    // Ctrl-C while a program runs stops it and returns to the prompt.
    s.send(".PROGRAM spin()\r");
    REQUIRE(s.expect("   1  "));  // while a program is typed, the prompt is the step number
    // Endless, and slow in real time: every motion is sampled and checked.
    s.send("    WHILE TRUE DO\r        MOVE #PPOINT(0, -90, 90, 0, 0, 0)\r");
    s.send("        MOVE #PPOINT(20, -90, 90, 0, 0, 0)\r    END\r");
    REQUIRE(s.expect("   5  "));
    s.send(".END\r");
    REQUIRE(s.expect(". "));
    s.send("EXECUTE spin\r");
    REQUIRE(s.expect("EXECUTE spin"));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    s.send("\x03");
    REQUIRE(s.expect("*Program interrupted*", 5));
    REQUIRE(s.expect(". "));
    s.send("STATUS\r");
    REQUIRE(s.expect("State: interrupted at step"));
    REQUIRE(s.expect(". "));
    s.send("ABORT\r");
    REQUIRE(s.expect(". "));
    s.send("PROCEED\r");
    REQUIRE(s.expect("*No program to resume*"));

    // STORE asks before replacing a file when interactive.
    s.send("STORE kept\r");
    REQUIRE(s.expect(". "));
    s.send("STORE kept\r");
    REQUIRE(s.expect("Replace file? (Y/N)"));
    s.send("y\r");
    REQUIRE(s.expect(". "));

    // ZERO asks first when interactive; "n" keeps everything.
    s.send("ZERO\r");
    REQUIRE(s.expect("Are you sure (Y/N)?"));
    s.send("n\r");
    // Wait for the prompt: libedit switches the tty mode back when it reads the next line and
    // may drop keys typed ahead of that (one CI-like run timed out here).
    REQUIRE(s.expect(". "));
    s.send("DIRECTORY\r");
    REQUIRE(s.expect("spin()"));

    // Ctrl-D while a program is typed ends it as .END would; the monitor goes on.
    s.send(".PROGRAM typed()\r");
    REQUIRE(s.expect("   1  "));
    s.send("    TYPE 5\r");
    REQUIRE(s.expect("   2  "));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // libedit's tty mode (below)
    s.send("\x04");
    REQUIRE(s.expect(". "));
    s.send("EXECUTE typed\r");
    REQUIRE(s.expect("Program completed: typed"));

    s.send("WHERE\r");
    REQUIRE(s.expect("         J1"));
    REQUIRE(s.expect(". "));
    // Ctrl-D on an empty line. libedit may still be switching the tty mode when the key
    // arrives (and the switch can drop it), so it is sent again if the monitor is still up.
    int rc = -1;
    for (int k = 0; k < 3 && rc < 0; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      s.send(k == 0 ? "\x04" : "\x15\x04");  // a retry first clears the line (Ctrl-U)
      rc = s.wait_exit(3);
    }
    INFO(s.seen().substr(s.seen().size() > 400 ? s.seen().size() - 400 : 0));
    CHECK(rc == 0);
  }
  const std::string history = asimov::test::slurp(dir / "home" / ".asimov_history");
  CHECK(history.find("WHERE") != std::string::npos);
  CHECK(history.find("EXECUTE") != std::string::npos);
  CHECK(asimov::test::slurp(dir / "kept.v2").find(".PROGRAM spin()") != std::string::npos);
  {
    PtySession s(dir, dir / "home");  // the history survives the session
    REQUIRE(s.expect(". "));
    s.send("\x10\r");  // the last line of the previous session: WHERE
    REQUIRE(s.expect("         J1"));
    s.send("QUIT\r");
    CHECK(s.wait_exit() == 0);
  }
}
