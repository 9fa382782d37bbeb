// Ctrl-C during `asimov run`: the program stops where it is (the arm at its last checked pose),
// the report and trace are still written, exit 130. The signal is sent once the process has
// installed its handler (read from /proc/PID/status), so the test does not depend on timing.
// Catch2 catches SIGINT itself, and a forked child keeps that until it execs, so the handler only
// counts once /proc/PID/exe is asimov (exec resets caught signals to their default).
#include "../support/run_cli.hpp"
#include "app/sigint.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using asimov::test::scratch_dir;
using json = nlohmann::json;

// True once `pid` runs asimov and catches SIGINT (SigCgt mask of /proc/PID/status). The binary
// is read first: any status read after it is the new program's.
bool catches_sigint(pid_t pid) {
  const std::string proc = "/proc/" + std::to_string(pid);
  std::error_code ec;
  if (!std::filesystem::equivalent(std::filesystem::read_symlink(proc + "/exe", ec), ASIMOV_BINARY, ec) || ec)
    return false;
  std::ifstream status(proc + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1;
  return false;
}

// Starts `asimov args...` with stdout and stderr to files; `signal` (SIGINT) once the handler is in place.
int run_and_interrupt(const std::vector<std::string>& args, const std::string& out_file, int signal = SIGINT) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    std::vector<char*> argv{const_cast<char*>(ASIMOV_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(ASIMOV_BINARY, argv.data());
    ::_exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!catches_sigint(pid) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  CHECK(catches_sigint(pid));  // if not, the SIGINT below still ends it
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // let it move a while
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

}  // namespace

TEST_CASE("Ctrl-C in asimov run stops the arm inside a motion, writes the report and exits 130") {
  const auto dir = scratch_dir();
  const auto program = dir / "spin.v2", report = dir / "spin.json", trace = dir / "spin_trace.json",
             output = dir / "spin.txt";
  std::ofstream(program) << ".PROGRAM spin()\n"
                            "  WHILE TRUE DO\n"
                            "    MOVE #PPOINT(-60, -90, 90, 0, 0, 0)\n"
                            "    MOVE #PPOINT(60, -90, 90, 0, 0, 0)\n"
                            "  END\n"
                            ".END\n";
  const int rc = run_and_interrupt({"run", program.string(), "--report", report.string(), "--trace", trace.string()},
                                   output.string());
  const std::string text = asimov::test::slurp(output);
  INFO(text);
  CHECK(rc == 130);
  CHECK(text.find("*Program interrupted*") != std::string::npos);

  const json doc = json::parse(asimov::test::slurp(report));
  CHECK(doc["status"] == "interrupted");
  CHECK(doc["error"]["message"] == "*Program interrupted*");
  CHECK(doc["sim_time_s"].get<double>() > 0);
  // The endless program only stops inside a motion or between the two MOVEs; a stop inside a
  // motion says where the arm is, between its start and its target on J1.
  if (doc.contains("interrupt")) {
    CHECK(text.find("motion halted at t = ") != std::string::npos);
    const double f = doc["interrupt"]["path_fraction"].get<double>();
    CHECK(f >= 0);
    CHECK(f <= 1);
    const double j1 = doc["interrupt"]["joints_deg"][0].get<double>();
    CHECK(j1 >= -60);
    CHECK(j1 <= 60);
    CHECK(doc["interrupt"]["time_s"].get<double>() == Approx(doc["sim_time_s"].get<double>()));
  }
  const json tr = json::parse(asimov::test::slurp(trace));
  CHECK(tr["samples"].size() > 2);
}

// A wait with a part in the cell and a blinking signal walks the devices' clock change by change
// (2,000,000 changes for this WAIT.EVENT): Ctrl-C and SIGTERM stop it between two checked poses.
TEST_CASE("Ctrl-C and SIGTERM stop a WAIT.EVENT with parts moving, and the report is written") {
  const auto dir = scratch_dir() / "wait-event";
  std::filesystem::create_directories(dir);
  const auto program = dir / "waitev.v2", cell = dir / "blink.yaml", output = dir / "out.txt";
  std::ofstream(program) << ".PROGRAM waitev()\n  WAIT.EVENT , 100000\n  TYPE \"done\"\n.END\n";
  std::ofstream(cell) << "objects:\n  - {name: table, box: [700, 1200, 40], at: [750, 0, -420, 0, 0, 0]}\n"
                         "parts:\n  - {name: cube, box: [40, 40, 40], at: [600, 0, -380, 0, 0, 0]}\n"
                         "logic:\n  - {at: 0, set: 2001, to: on}\n"
                         "  - {when: 2001, is: on, after: 0.05, set: 2001, to: off}\n"
                         "  - {when: 2001, is: off, after: 0.05, set: 2001, to: on}\n";
  for (const int signal : {SIGINT, SIGTERM}) {
    INFO(signal);
    const auto report = dir / ("report" + std::to_string(signal) + ".json");
    const auto t0 = std::chrono::steady_clock::now();
    const int rc = run_and_interrupt({"run", program.string(), "--cell", cell.string(), "--report", report.string()},
                                     output.string(), signal);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 20);
    const std::string text = asimov::test::slurp(output);
    INFO(text);
    CHECK(rc == (signal == SIGINT ? 130 : 1000 + SIGTERM));  // SIGTERM: the process ends by it, as its sender expects
    CHECK(text.find("*Program interrupted*") != std::string::npos);
    CHECK(text.find("WAIT.EVENT , 100000") != std::string::npos);
    CHECK(text.find("done") == std::string::npos);
    const json r = json::parse(asimov::test::slurp(report));
    CHECK(r["status"] == "interrupted");
  }
}

// The devices' clock costs linear time in its changes: a 0.1 s blink for the whole WAIT limit
// (3600 s, 72,000 changes) with a part in the cell took past 60 s when every change copied the
// clock with its event log.
TEST_CASE("a WAIT on a signal nothing drives, beside a blinking rule and a part, ends at the wait limit in seconds") {
  const auto dir = scratch_dir() / "wait-blink";
  std::filesystem::create_directories(dir);
  const auto program = dir / "waitsig.v2", cell = dir / "blink.yaml";
  std::ofstream(program) << ".PROGRAM waitsig()\n  WAIT SIG(1005)\n.END\n";
  std::ofstream(cell) << "objects:\n  - {name: table, box: [700, 1200, 40], at: [750, 0, -420, 0, 0, 0]}\n"
                         "parts:\n  - {name: cube, box: [40, 40, 40], at: [600, 0, -380, 0, 0, 0]}\n"
                         "logic:\n  - {at: 0, set: 2001, to: on}\n"
                         "  - {when: 2001, is: on, after: 0.05, set: 2001, to: off}\n"
                         "  - {when: 2001, is: off, after: 0.05, set: 2001, to: on}\n";
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = asimov::test::run_cli("run " + program.string() + " --cell " + cell.string());
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 30);
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("*Wait limit exceeded*  still false after 3600 s") != std::string::npos);
}

// The second Ctrl-C of a batch run ends the process at once, whatever it is doing (a run that does
// not reach its next check, such as a long cell load, can still be stopped); the monitor's handler
// (once = false) stays, so each Ctrl-C only stops the command under way. Run in a forked child:
// its exit status is the evidence (Catch2's own SIGINT handler is replaced there only).
TEST_CASE("the first Ctrl-C sets the flag, a second one ends a batch run at once, the monitor keeps its handler") {
  const auto child_status = [](bool once) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      asimov::app::install_sigint(once);
      asimov::app::sigint_flag() = false;
      ::raise(SIGINT);
      if (!asimov::app::sigint_flag()) ::_exit(2);  // the first one must only set the flag
      asimov::app::sigint_flag() = false;
      ::raise(SIGINT);
      ::_exit(asimov::app::sigint_flag() ? 0 : 3);  // reached only if the second one was caught
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
  };
  const int batch = child_status(true);
  CHECK(WIFSIGNALED(batch));
  CHECK((WIFSIGNALED(batch) && WTERMSIG(batch) == SIGINT));
  const int monitor = child_status(false);
  CHECK(WIFEXITED(monitor));
  CHECK((WIFEXITED(monitor) && WEXITSTATUS(monitor) == 0));
}
