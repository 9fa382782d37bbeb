// Monitor sessions (dialect §9) beyond the sample cases: the sample sessions
// programs/monitor/NAME.session (run by `asimov test`, CTest "programs: monitor") use every
// command of the table; STORE and LOAD round trips and failures; monitor usage errors.
#include "asimov/interpreter/monitor.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using asimov::test::slurp;
using asimov::test::source_path;

namespace {

struct Session {
  int exit_code = -1;
  std::string out, err;
  fs::path dir;  // where it ran
};

// A fresh folder with the .v2 files of programs/monitor.
fs::path session_dir(const std::string& name) {
  const fs::path dir = asimov::test::scratch_dir() / ("monitor-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(source_path("programs/monitor")))
    if (e.path().extension() == ".v2") fs::copy_file(e.path(), dir / e.path().filename());
  return dir;
}

Session run_session(const std::string& name, const std::string& input) {
  Session s;
  s.dir = session_dir(name);
  std::ofstream(s.dir / "stdin.txt", std::ios::binary) << input;
  const std::string cmd = "cd '" + s.dir.string() + "' && " + ASIMOV_BINARY + " monitor" +
                          " <stdin.txt >stdout.txt 2>stderr.txt";
  const int status = std::system(cmd.c_str());
  s.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  s.out = slurp(s.dir / "stdout.txt");
  s.err = slurp(s.dir / "stderr.txt");
  return s;
}

std::vector<fs::path> sessions() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(source_path("programs/monitor")))
    if (e.path().extension() == ".session") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("the monitor sessions use every command of the table", "[monitor]") {
  std::set<asimov::interpreter::Command> used;
  bool program_entry = false;
  for (const fs::path& session : sessions()) {
    std::istringstream in(slurp(session));
    std::string line;
    while (std::getline(in, line)) {
      std::size_t end = 0;
      while (end < line.size() && std::isalpha(static_cast<unsigned char>(line[end]))) ++end;
      const auto m = asimov::interpreter::match_command(line.substr(0, end));
      if (m.match == asimov::interpreter::Match::found) used.insert(m.command);
      program_entry = program_entry || line.rfind(".PROGRAM", 0) == 0;
    }
  }
  for (int c = 0; c < static_cast<int>(asimov::interpreter::Command::count); ++c) {
    INFO(asimov::interpreter::command_info(static_cast<asimov::interpreter::Command>(c)).name);
    CHECK(used.count(static_cast<asimov::interpreter::Command>(c)) == 1);
  }
  CHECK(program_entry);
}

TEST_CASE("STORE writes shortest round-trip numbers that LOAD reads back bit-equal", "[monitor]") {
  const Session s = run_session("store-numbers",
                                "DO x = 0.1\nDO y = 1/3\nDO big = 1.5e300\nDO tiny = -2.5e-8\n"
                                "POINT p = TRANS(10, 20, 30, 45, 90, -135)\nDO $s = \"text\"\nSTORE saved\n");
  REQUIRE(s.exit_code == 0);
  const std::string text = slurp(s.dir / "saved.v2");
  CHECK(text.find("x 0.1\n") != std::string::npos);
  CHECK(text.find("y 0.3333333333333333\n") != std::string::npos);
  CHECK(text.find("big 1.5e+300\n") != std::string::npos);
  CHECK(text.find("tiny -2.5e-08\n") != std::string::npos);
  CHECK(text.find("$s \"text\"\n") != std::string::npos);
  // Reading it back and storing again gives the same file.
  std::ofstream(s.dir / "again.txt") << "LOAD saved\nSTORE saved2\n";
  const std::string cmd = "cd '" + s.dir.string() + "' && " + ASIMOV_BINARY + " monitor <again.txt >/dev/null 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  // Reals and strings come back bit-equal; locations within 1e-12 (decompose, TRANS).
  const std::string again = slurp(s.dir / "saved2.v2");
  CHECK(again.substr(again.find(".REALS")) == text.substr(text.find(".REALS")));
  CHECK(again.find("p 10 20 30 45") != std::string::npos);
  for (const auto& e : fs::directory_iterator(s.dir))  // no temporary left behind
    CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("a failing STORE leaves the old file whole, and LOAD of a damaged file marks its broken program", "[monitor]") {
  const Session s = run_session("store-fail",
                                "LOAD square\nSTORE keep\nDO extra = 1\nSTORE keep/inside.v2\n"
                                "LOAD damaged\nDIRECTORY\nLISTR\n");
  const std::string kept = slurp(s.dir / "keep.v2");
  CHECK(kept.find(".PROGRAM square(a, $label)") != std::string::npos);
  CHECK(kept.find("extra") == std::string::npos);
  CHECK(s.out.find("*Cannot write file*  keep/inside.v2") != std::string::npos);
  CHECK(s.out.find(" damaged.v2:6:19  (broken, step 1)") != std::string::npos);
  // As V+ loads (dialect §8): fine() loads, broken() is loaded marked not executable.
  CHECK(s.out.find("broken()\nfine()\n") != std::string::npos);
  CHECK(s.out.find("count           3\nextra           1\n") != std::string::npos);
  for (const auto& e : fs::directory_iterator(s.dir))
    CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("monitor usage: a missing FILE or a bad cell exits 1, and asimov alone is the monitor", "[monitor]") {
  CHECK(asimov::test::run_cli("monitor /nonexistent/x.v2").exit_code == 1);
  CHECK(asimov::test::run_cli("monitor --cell /nonexistent/cell.yaml").exit_code == 1);
  const auto alone = asimov::test::run_cli("", "where\nfoo\n");
  CHECK(alone.exit_code == 0);
  CHECK(alone.out.find("         J1") != std::string::npos);
  CHECK(alone.out.find("*Unknown command*  foo") != std::string::npos);
  CHECK(alone.out.find(". ") == std::string::npos);  // no prompt when stdin is not a terminal
  const auto strict = asimov::test::run_cli("monitor --strict", "foo\nwhere\n");
  CHECK(strict.exit_code == 2);
  CHECK(strict.out.find("J1") == std::string::npos);
}
