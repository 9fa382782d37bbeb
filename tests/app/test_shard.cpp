// `asimov test --shard K/N`, `--list`, `--merge-junit` (app/cmd_test.cpp, docs/scale-out.md):
// shards partition a suite by case name, their JUnit files merge into the whole suite's, and the
// [k/N] progress prefix appears only on a terminal.
#include "app/commands.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using asimov::test::run_cli;
using asimov::test::slurp;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) out.push_back(l);
  return out;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

// A suite of `n` passing cases c0 .. c{n-1}.
fs::path small_suite(const std::string& name, int n) {
  const fs::path dir = asimov::test::scratch_dir() / ("shard-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (int i = 0; i < n; ++i) {
    std::ofstream(dir / ("c" + std::to_string(i) + ".v2")) << ".PROGRAM c()\n    TYPE " << i << "\n.END\n";
    std::ofstream(dir / ("c" + std::to_string(i) + ".expect.json")) << "{\"exit\": 0, \"stdout\": [\"" << i << "\"]}";
  }
  return dir;
}

}  // namespace

TEST_CASE("shard assignment: K/N parsing, a stable hash of the name, every case in one shard") {
  int k = 0, n = 0;
  CHECK(asimov::app::parse_shard("1/3", k, n));
  CHECK((k == 1 && n == 3));
  CHECK(asimov::app::parse_shard("3/3", k, n));
  CHECK(asimov::app::parse_shard("1/1", k, n));
  for (const char* bad : {"0/3", "4/3", "3", "/3", "1/", "a/b", "1/0", "-1/3", "1/3/3", "1 /3", "1/1000000", ""})
    CHECK_FALSE(asimov::app::parse_shard(bad, k, n));
  // FNV-1a: the value for a name never changes (CI runners on other machines agree).
  // Pinned values (FNV-1a 64 of the name is 0x1057c95e697cc706; of "a" 0xaf63dc4c8601ec8c).
  CHECK(asimov::app::shard_of("programs/demo/crash", 3) == 1);
  CHECK(asimov::app::shard_of("programs/demo/crash", 1000) == 942);
  CHECK(asimov::app::shard_of("a", 1000) == 996);
  CHECK(asimov::app::shard_of("", 7) == 2);
  std::vector<int> seen(7, 0);
  for (int i = 0; i < 700; ++i) ++seen[static_cast<std::size_t>(asimov::app::shard_of("case" + std::to_string(i), 7))];
  for (int count : seen) CHECK((count > 50 && count < 150));  // spread, not all in one
}

TEST_CASE("asimov test programs --shard k/3 --list: the three shards partition the suite exactly") {
  const std::string programs = std::string(ASIMOV_SOURCE_DIR) + "/programs";
  const auto all = run_cli("test " + programs + " --list");
  REQUIRE(all.exit_code == 0);
  const auto every = lines_of(all.out);
  REQUIRE(every.size() > 50);
  std::multiset<std::string> union_of_shards;
  for (int k = 1; k <= 3; ++k) {
    const auto shard = run_cli("test " + programs + " --list --shard " + std::to_string(k) + "/3");
    INFO(shard.err);
    REQUIRE(shard.exit_code == 0);
    const auto names = lines_of(shard.out);
    CHECK(!names.empty());
    for (const auto& name : names) CHECK(asimov::app::shard_of(name, 3) == k - 1);
    union_of_shards.insert(names.begin(), names.end());
  }
  CHECK(std::vector<std::string>(union_of_shards.begin(), union_of_shards.end()) == every);  // each once
}

TEST_CASE("asimov test --shard runs only its cases, the shards' JUnit files merge into the whole suite") {
  const fs::path dir = small_suite("merge", 9);
  std::vector<fs::path> files;
  std::size_t ran = 0;
  for (int k = 1; k <= 4; ++k) {
    const fs::path junit = dir / ("shard" + std::to_string(k) + ".xml");
    const auto r = run_cli("test " + q(dir) + " --shard " + std::to_string(k) + "/4 --junit " + q(junit));
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    const auto out_lines = lines_of(r.out);  // one vector: begin and end of two temporaries would not meet
    const auto passes = std::count_if(out_lines.begin(), out_lines.end(), [](const std::string& l) {
      return l.rfind("PASS ", 0) == 0;
    });
    ran += static_cast<std::size_t>(passes);
    const std::string xml = slurp(junit);
    CHECK(xml.find("<property name=\"shard\" value=\"" + std::to_string(k) + "/4\"/>") != std::string::npos);
    CHECK(xml.find("<property name=\"schema_version\" value=\"1\"/>") != std::string::npos);
    files.push_back(junit);
  }
  CHECK(ran == 9);
  std::string inputs;
  for (const auto& f : files) inputs += " " + q(f);
  const fs::path merged = dir / "all.xml";
  auto m = run_cli("test --merge-junit " + q(merged) + inputs);
  INFO(m.out << m.err);
  REQUIRE(m.exit_code == 0);
  CHECK(m.out.find("9 cases from 4 files, 0 failed") != std::string::npos);
  const std::string xml = slurp(merged);
  CHECK(xml.find("<testsuites name=\"asimov test\" tests=\"9\" failures=\"0\"") != std::string::npos);
  for (int i = 0; i < 9; ++i) CHECK(xml.find("<testcase name=\"c" + std::to_string(i) + "\"") != std::string::npos);
  CHECK(xml.find("<property name=\"shard\"") == std::string::npos);

  // A merge that would count a case twice, a file that is not ours, no inputs: exit 1.
  m = run_cli("test --merge-junit " + q(dir / "twice.xml") + " " + q(files[0]) + " " + q(merged));
  CHECK(m.exit_code == 1);
  CHECK(m.err.find("is in an earlier file too") != std::string::npos);
  std::ofstream(dir / "other.xml") << "<testsuite/>";
  m = run_cli("test --merge-junit " + q(dir / "x.xml") + " " + q(dir / "other.xml"));
  CHECK(m.exit_code == 1);
  CHECK(m.err.find("not a JUnit file of asimov test --junit") != std::string::npos);
  CHECK(run_cli("test --merge-junit " + q(dir / "x.xml")).exit_code == 1);
  CHECK(run_cli("test " + q(dir) + " --shard 5/4").exit_code == 1);

  // More shards than cases: an empty shard succeeds and still writes its (empty) JUnit file.
  const fs::path one = small_suite("one", 1);
  int empty_shards = 0;
  for (int k = 1; k <= 3; ++k) {
    const auto r = run_cli("test " + q(one) + " --shard " + std::to_string(k) + "/3 --junit " + q(one / "j.xml"));
    CHECK(r.exit_code == 0);
    if (r.out.find("0 cases in shard") != std::string::npos) {
      ++empty_shards;
      CHECK(slurp(one / "j.xml").find("tests=\"0\"") != std::string::npos);
    }
  }
  CHECK(empty_shards == 2);
}

TEST_CASE("asimov test: [k/N] progress only on a terminal") {
  const fs::path dir = small_suite("progress", 3);
  const auto plain = run_cli("test " + q(dir));
  REQUIRE(plain.exit_code == 0);
  CHECK(plain.out.find("[1/3]") == std::string::npos);
  // script(1) gives the command a terminal as stdout (skipped where util-linux script is missing).
  if (std::system("command -v script >/dev/null 2>&1") != 0) return;
  const fs::path log = dir / "tty.txt";
  const std::string cmd = "script -qec \"" + std::string(ASIMOV_BINARY) + " test " + dir.string() + "\" /dev/null > " +
                          log.string() + " 2>&1 </dev/null";
  CHECK(std::system(cmd.c_str()) == 0);
  const std::string tty = slurp(log);
  INFO(tty);
  CHECK(tty.find("[1/3] PASS ") != std::string::npos);
  CHECK(tty.find("[3/3] PASS ") != std::string::npos);
}
