// Outputs that never destroy (issue 29): every output file (--report, --trace, --replay, --junit,
// pairs --cache, STORE) replaces only a regular file, never an input of the same run nor another
// output of it, and a write that fails names the real target and the reason while the run keeps
// its own exit code (a collision stays 3; a run that ended well and lost an output exits 5).
#include "support/run_cli.hpp"

#include "asimov/core/output_file.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include <sys/stat.h>
#include <sys/wait.h>

using namespace asimov;
using test::run_cli;
using test::slurp;
using test::source_path;
namespace fs = std::filesystem;

namespace {

fs::path fresh(const std::string& name) {
  const auto dir = test::scratch_dir() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string crash_copy(const fs::path& dir) {
  const auto p = dir / "crash.v2";
  fs::copy_file(source_path("programs/demo/crash.v2"), p, fs::copy_options::overwrite_existing);
  return p.string();
}

bool is_fifo_node(const fs::path& p) {
  struct stat st {};
  return ::lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

}  // namespace

TEST_CASE("an output that is an input of the run is refused before it runs", "[cli][outputs]") {
  const auto dir = fresh("outputs-inputs");
  const std::string program = crash_copy(dir);
  const std::string before = slurp(program);
  auto r = run_cli("run " + program + " --report " + program);
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cannot write file*  " + program + ": is the program file (an input of this run); --report would overwrite it\n");
  CHECK(slurp(program) == before);

  const auto cell = dir / "cell.yaml";
  std::ofstream(cell) << "robot: puma560\n";
  r = run_cli("run " + program + " --cell " + cell.string() + " --trace " + cell.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("is the cell file (an input of this run); --trace would overwrite it") != std::string::npos);
  CHECK(slurp(cell) == "robot: puma560\n");

  // The same file by another name (a relative path, a link) is the same input.
  fs::create_symlink("crash.v2", dir / "alias.v2");
  r = run_cli("run " + program + " --replay " + (dir / "alias.v2").string());
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("is the program file") != std::string::npos);
  CHECK(slurp(program) == before);
}

TEST_CASE("two outputs on one path are refused", "[cli][outputs]") {
  const auto dir = fresh("outputs-twice");
  const std::string program = crash_copy(dir);
  const std::string out = (dir / "R.json").string();
  const auto r = run_cli("run " + program + " --report " + out + " --trace " + out);
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*Cannot write file*  " + out + ": is given to both --report and --trace; each output needs its own file\n");
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("a FIFO, a device or a link to one is never replaced", "[cli][outputs]") {
  const auto dir = fresh("outputs-special");
  const std::string program = crash_copy(dir);
  const auto fifo = dir / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  fs::create_symlink("fifo", dir / "to-fifo");
  for (const char* opt : {"--report", "--trace", "--replay"}) {
    INFO(opt);
    auto r = run_cli("run " + program + " " + opt + " " + fifo.string());
    CHECK(r.exit_code == 1);
    CHECK(r.err == "*Cannot write file*  " + fifo.string() + ": is a FIFO, not a regular file; an output replaces only a regular file\n");
    r = run_cli("run " + program + " " + opt + " " + (dir / "to-fifo").string());
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("is a FIFO, not a regular file (the link leads to") != std::string::npos);
    CHECK(is_fifo_node(fifo));
    CHECK(fs::is_symlink(dir / "to-fifo"));
    r = run_cli("run " + program + " " + opt + " /dev/null");
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("/dev/null: is a device, not a regular file") != std::string::npos);
  }
  CHECK(fs::is_character_file("/dev/null"));
  auto r = run_cli("pairs --samples 20 --cache " + fifo.string());
  CHECK(r.exit_code == 1);  // refused before anything is computed (reading a FIFO would block)
  CHECK(r.err.find("is a FIFO") != std::string::npos);
  CHECK(is_fifo_node(fifo));
  r = run_cli("test " + source_path("programs/demo/pick_place.v2") + " --junit " + fifo.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("is a FIFO") != std::string::npos);
  const auto stored = dir / "stored.v2";  // STORE adds .v2 to a name without an extension
  REQUIRE(::mkfifo(stored.c_str(), 0644) == 0);
  r = run_cli("monitor", "LOAD " + program + "\nSTORE " + stored.string() + "\nQUIT\n");
  CHECK(r.out.find("is a FIFO") != std::string::npos);
  CHECK(is_fifo_node(stored));
  // LOAD of that FIFO: named as what it is (was *File not found*), refused before any open (an
  // open with no writer would block the monitor for ever), and the session goes on.
  r = run_cli("monitor", "LOAD " + stored.string() + "\nLOAD " + (dir / "none.v2").string() + "\nQUIT\n");
  CHECK(r.out.find("*Cannot read file*  " + stored.string() + ": is a FIFO, not a regular file") != std::string::npos);
  CHECK(r.out.find("*File not found*  " + (dir / "none.v2").string()) != std::string::npos);
  CHECK(is_fifo_node(stored));
}

TEST_CASE("an output through a link replaces the file it names and keeps the link", "[cli][outputs]") {
  const auto dir = fresh("outputs-link");
  const std::string program = crash_copy(dir);
  fs::create_directories(dir / "real");
  std::ofstream(dir / "real" / "report.json") << "old\n";
  fs::create_symlink("real/report.json", dir / "report.json");
  const auto r = run_cli("run " + program + " --report " + (dir / "report.json").string());
  CHECK(r.exit_code == 3);
  CHECK(fs::is_symlink(dir / "report.json"));
  CHECK(slurp(dir / "real" / "report.json").find("\"status\": \"collision\"") != std::string::npos);
  for (const auto& e : fs::directory_iterator(dir / "real")) CHECK(e.path().filename() == "report.json");
}

TEST_CASE("a lost output keeps the run's exit code and is never silent", "[cli][outputs]") {
  const auto dir = fresh("outputs-full");
  const auto full = [&](const std::string& args) {
    const auto err = dir / "err";
    const int status = std::system((std::string(ASIMOV_BINARY) + " " + args + " </dev/null >/dev/full 2>" + err.string()).c_str());
    return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err)};
  };
  auto [rc, err] = full("run " + source_path("programs/demo/crash.v2") + " --report -");
  CHECK(rc == 3);  // the collision, though its report was lost
  CHECK(err.find("*Cannot write file*  standard output") != std::string::npos);
  std::tie(rc, err) = full("run " + source_path("programs/demo/pick_place.v2") + " --report -");
  CHECK(rc == 5);
  CHECK(err.find("*Cannot write file*  standard output") != std::string::npos);
}

TEST_CASE("core::write_output_file names the real target and the reason", "[outputs]") {
  const auto dir = fresh("outputs-core");
  const auto missing = (dir / "no" / "f.json").string();
  auto w = core::write_output_file(missing, "x");
  REQUIRE_FALSE(w.ok());
  CHECK(w.error().message == missing + ": no folder " + (dir / "no").string());
  // A link into a missing folder: the message names where the link leads.
  fs::create_symlink("gone/target.json", dir / "dangling");
  w = core::write_output_file((dir / "dangling").string(), "x");
  REQUIRE_FALSE(w.ok());
  CHECK(w.error().message.find((dir / "gone" / "target.json").string()) == 0);
  // Written, mode kept, nothing left beside it.
  const auto f = dir / "f.txt";
  std::ofstream(f) << "old";
  fs::permissions(f, fs::perms::owner_read | fs::perms::owner_write);
  REQUIRE(core::write_output_file(f.string(), "new").ok());
  CHECK(slurp(f) == "new");
  CHECK((fs::status(f).permissions() & fs::perms::all) == (fs::perms::owner_read | fs::perms::owner_write));
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.path().filename().string().find(".tmp") == std::string::npos;
  CHECK(files == 2);  // f.txt and the dangling link
  CHECK(core::same_file(f.string(), (dir / "." / "f.txt").string()));
  CHECK_FALSE(core::same_file(f.string(), (dir / "g.txt").string()));
}

TEST_CASE("asimov pairs shows a name's escape sequences as '?'", "[cli][pairs]") {
  const auto dir = fresh("outputs-pairs-names");
  const auto cell = dir / "cell.yaml";
  std::ofstream(cell) << "objects:\n  - {name: \"\\e[2Jbox\", box: [10, 10, 10], at: [600, 0, -900, 0, 0, 0]}\n";
  const auto r = run_cli("pairs " + cell.string() + " --samples 20 --no-cache");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find('\x1b') == std::string::npos);
  CHECK(r.out.find("?[2Jbox") != std::string::npos);
}

TEST_CASE("a monitor line longer than 64 KiB is refused without echo, the session goes on", "[cli][monitor][hostile]") {
  const auto r = run_cli("monitor", std::string(1000000, 'A') + "\nDO TYPE 6 * 7\n");
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("*Line too long*  a monitor line is longer than 65536 bytes (docs/limits.md)\n") == 0);
  CHECK(r.out.find("42") != std::string::npos);
  CHECK(r.out.size() < 1000);
  const auto strict = run_cli("monitor --strict", std::string(70000, 'B') + "\nDO TYPE 1\n");
  CHECK(strict.exit_code == 2);
  CHECK(strict.out.find("*Line too long*") != std::string::npos);
}
