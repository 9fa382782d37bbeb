// Exit codes for hostile command lines (issue 17): 1 means nothing ran, so output files are
// checked first; pairs never creates folders nor leaves a temporary file; sample counts are
// checked; files that are folders or devices are read with a bound.
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

using namespace asimov;
using test::run_cli;
using test::source_path;

TEST_CASE("run: --report, --trace, --replay into a missing folder fail before running", "[cli][hostile]") {
  const auto dir = test::scratch_dir();
  const std::string program = (dir / "prints.v2").string();
  std::ofstream(program) << ".PROGRAM prints()\n  TYPE \"ran\"\n.END\n";
  for (const char* opt : {"--report", "--trace", "--replay"}) {
    INFO(opt);
    const auto target = dir / "no-such-folder" / "out.json";
    const auto r = run_cli("run " + program + " " + opt + " " + target.string());
    CHECK(r.exit_code == 1);
    CHECK(r.out.empty());  // nothing ran: no TYPE output
    CHECK(r.err == "*Cannot write file*  " + target.string() + ": no folder " + (dir / "no-such-folder").string() + "\n");
  }
  const auto r = run_cli("run " + program + " --report " + dir.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cannot write file*  " + dir.string() + ": is a folder, not a file; an output replaces only a regular file\n");
}

TEST_CASE("pairs --cache never creates folders nor leaves FILE.tmp", "[cli][hostile][pairs]") {
  const auto dir = test::scratch_dir() / "pairs-cache";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto missing = dir / "missing" / "cell.pairs";
  auto r = run_cli("pairs --samples 50 --cache " + missing.string());
  CHECK(r.exit_code == 0);  // the matrix is printed; the cache is only a warning
  CHECK_THAT(r.err, Catch::Contains("Warning: cannot write the pair cache"));
  CHECK_FALSE(std::filesystem::exists(dir / "missing"));
  const auto good = dir / "cell.pairs";
  r = run_cli("pairs --samples 50 --cache " + good.string());
  CHECK(r.exit_code == 0);
  CHECK(std::filesystem::exists(good));
  for (const auto& e : std::filesystem::directory_iterator(dir))
    CHECK(e.path().filename() == "cell.pairs");  // no cell.pairs.tmp beside it
  std::filesystem::remove_all(dir);
}

TEST_CASE("pairs --samples must be 1..10000000", "[cli][hostile][pairs]") {
  for (const char* n : {"0", "-5", "10000001", "1e400", "x"}) {
    INFO(n);
    const auto r = run_cli(std::string("pairs --no-cache --samples ") + n);
    CHECK(r.exit_code == 1);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, Catch::Contains("--samples"));
    CHECK(r.err.size() < 300);  // no 310-digit number
  }
}

TEST_CASE("run: --cell that is a folder or /dev/zero, a program that is a folder", "[cli][hostile]") {
  const auto dir = test::scratch_dir();
  const auto t0 = std::chrono::steady_clock::now();
  auto r = run_cli("run " + source_path("programs/demo/pick_place.v2") + " --cell /dev/zero");
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cell error*  /dev/zero: is larger than 64 MiB, the limit for this kind of file\n");
  r = run_cli("run " + source_path("programs/demo/pick_place.v2") + " --cell " + dir.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cell error*  " + dir.string() + ": is a directory, not a file\n");
  r = run_cli("check " + dir.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cannot read file*  " + dir.string() + ": is a folder, not a file\n");
  r = run_cli("check /dev/zero");
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cannot read file*  /dev/zero: is a device, not a regular file\n");
  r = run_cli("run " + (dir / "no-such.v2").string());
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*File not found*  " + (dir / "no-such.v2").string() + "\n");
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 30);
}

// Starts `asimov test` on a case that never ends, sends `signal` once the case runs and returns
// the wait status; `scratch` is the command's scratch folder, `log` its stdout.
int interrupt_suite(int signal, std::filesystem::path& scratch, std::string& log_text) {
  const auto dir = test::scratch_dir() / ("interrupted-suite-" + std::to_string(signal));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "spin.v2") << ".PROGRAM spin()\n  WHILE TRUE DO\n  END\n.END\n";
  std::ofstream(dir / "spin.expect.json") << R"({"exit": 0, "stdout": []})";
  const auto log = dir / "log.txt";
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    ::execl(ASIMOV_BINARY, ASIMOV_BINARY, "test", dir.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  scratch = std::filesystem::temp_directory_path() / ("asimov-test-" + std::to_string(pid));
  // Wait until the case runs (its scratch folder exists), then the signal.
  for (int i = 0; i < 200 && !std::filesystem::exists(scratch); ++i) ::usleep(50000);
  CHECK(std::filesystem::exists(scratch));
  ::usleep(300000);
  ::kill(pid, signal);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  log_text = test::slurp(log);
  std::filesystem::remove_all(dir);
  return status;
}

TEST_CASE("an interrupted asimov test removes its scratch folder and exits 130", "[cli][hostile][suite]") {
  std::filesystem::path scratch;
  std::string log;
  const int status = interrupt_suite(SIGINT, scratch, log);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  CHECK_FALSE(std::filesystem::exists(scratch));
  CHECK(log == "Interrupted: 0 of 1 case run, 0 failed\n");
}

TEST_CASE("asimov test stopped by SIGTERM or SIGHUP removes its scratch folder, then ends by that signal",
          "[cli][hostile][suite]") {
  for (const int signal : {SIGTERM, SIGHUP}) {
    CAPTURE(signal);
    std::filesystem::path scratch;
    std::string log;
    const int status = interrupt_suite(signal, scratch, log);
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal);
    CHECK_FALSE(std::filesystem::exists(scratch));
    CHECK(log == "Interrupted: 0 of 1 case run, 0 failed\n");
  }
}

// Run by the test below as a child process (hidden: not part of the suite).
TEST_CASE("scratch probe: fills the scratch folder, prints it", "[.scratch-probe]") {
  const auto dir = test::scratch_dir("probe");
  std::ofstream(dir / "file.txt") << "x";
  std::cout << "scratch: " << test::scratch_dir().string() << std::endl;
  if (std::getenv("ASIMOV_PROBE_FAIL")) CHECK(false);
}

TEST_CASE("a test process removes its scratch folder when it exits, passed or failed", "[cli][suite]") {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  REQUIRE_FALSE(ec);
  for (const char* fail : {"", "ASIMOV_PROBE_FAIL=1 "}) {
    CAPTURE(fail);
    std::string cmd = fail;
    cmd.append("'").append(self.string()).append("' '[.scratch-probe]' 2>&1");
    std::fflush(nullptr);
    FILE* pipe = ::popen(cmd.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    const int status = ::pclose(pipe);
    CHECK(WEXITSTATUS(status) == (*fail ? 1 : 0));
    const auto at = out.find("scratch: ");
    REQUIRE(at != std::string::npos);
    const auto folder = out.substr(at + 9, out.find('\n', at) - at - 9);
    const auto prefix = (std::filesystem::temp_directory_path() / "asimov-test-").string();
    REQUIRE(folder.rfind(prefix, 0) == 0);  // the child's own folder, not ours
    CHECK(folder != test::scratch_dir().string());
    CHECK_FALSE(std::filesystem::exists(folder));
  }
}
