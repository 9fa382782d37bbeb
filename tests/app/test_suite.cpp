// `asimov test` (app/suite.hpp, app/cmd_test.cpp): the matcher and its messages, the expected
// files, discovery, and the command end to end on small suites written to a scratch folder.
#include "app/suite.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
namespace suite = asimov::app::suite;
using asimov::test::run_cli;
using asimov::test::slurp;
using nlohmann::json;

namespace {

// A fresh folder for one test's suite.
fs::path suite_dir(const std::string& name) {
  const fs::path dir = asimov::test::scratch_dir() / ("suite-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

const char* kHello = ".PROGRAM hello()\n    TYPE \"hi\"\n    TYPE 6 * 7\n.END\n";
const char* kBroken = ".PROGRAM broken()\n    TYPE 1 / 0\n.END\n";

std::vector<std::string> report_diffs(const json& expected, const json& actual) {
  std::vector<std::string> diffs;
  suite::match_report(expected, actual, "report", diffs);
  return diffs;
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST_CASE("report matcher: subsets, ranges and the JSON path of a mismatch") {
  const json actual = json::parse(R"({"status": "collision", "poses_checked": 859,
      "collision": {"bodies": ["link4", "box"], "time_s": 3.37}, "accuracy": {"motions": 2}})");
  CHECK(report_diffs(json::parse(R"({"status": "collision"})"), actual).empty());
  CHECK(report_diffs(json::parse(R"({"poses_checked": {"min": 100}})"), actual).empty());
  CHECK(report_diffs(json::parse(R"({"poses_checked": 859.0})"), actual).empty());  // numbers as doubles
  CHECK(report_diffs(json::parse(R"({"collision": {"time_s": {"min": 3.3, "max": 3.5}}})"), actual).empty());

  auto d = report_diffs(json::parse(R"({"collision": {"bodies": ["link4", "table"]}})"), actual);
  REQUIRE(d.size() == 1);
  CHECK(d[0] == "report.collision.bodies[1]: expected \"table\", got \"box\"");

  d = report_diffs(json::parse(R"({"poses_checked": {"min": 1000000}})"), actual);
  REQUIRE(d.size() == 1);
  CHECK(d[0] == "report.poses_checked: expected a number in [1000000, inf], got 859");

  d = report_diffs(json::parse(R"({"collision": {"faces": [1, 2]}, "status": "completed"})"), actual);
  REQUIRE(d.size() == 2);
  CHECK(d[0] == "report.collision.faces: missing, expected [1,2]");
  CHECK(d[1] == "report.status: expected \"completed\", got \"collision\"");

  d = report_diffs(json::parse(R"({"collision": {"bodies": ["link4"]}})"), actual);
  REQUIRE(d.size() == 1);
  CHECK(d[0] == "report.collision.bodies: expected [\"link4\"], got [\"link4\",\"box\"]");

  d = report_diffs(json::parse(R"({"status": {"max": 1}})"), actual);
  REQUIRE(d.size() == 1);
  CHECK(d[0] == "report.status: expected a number in [-inf, 1], got \"collision\"");
}

TEST_CASE("first differing line of an output") {
  CHECK_FALSE(suite::first_line_difference("stdout", "a\nb\n", "a\nb\n"));
  CHECK(suite::first_line_difference("stdout", "a\nb\nc\n", "a\nx\nc\n") ==
        std::string("stdout line 2: expected \"b\", got \"x\""));
  CHECK(suite::first_line_difference("stdout", "a\nb\n", "a\n") ==
        std::string("stdout line 2: expected \"b\", got end of output"));
  CHECK(suite::first_line_difference("stderr", "", "oops\n") ==
        std::string("stderr line 1: expected end of output, got \"oops\""));
  CHECK(suite::first_line_difference("stdout", "a\n", "a") == std::string("stdout: expected a final newline"));
}

TEST_CASE("compare lists exit code, stdout, stderr and report differences") {
  suite::Expectation e;
  e.exit = 3;
  e.stdout_text = "hi\n";
  e.stderr_has = {"*Collision*"};
  e.report = json::parse(R"({"status": "collision"})");
  suite::Actual a;
  a.exit_code = 0;
  a.out = "ho\n";
  a.err = "Program completed: x\n";
  a.report_problem = "no report was written";
  const auto d = suite::compare(e, a);
  REQUIRE(d.size() == 4);
  CHECK(d[0] == "exit code: expected 3, got 0");
  CHECK(d[1] == "stdout line 1: expected \"hi\", got \"ho\"");
  CHECK(d[2] == "stderr: missing \"*Collision*\"");
  CHECK(d[3] == "report: no report was written");

  a.exit_code = 3;
  a.out = "hi\n";
  a.err = "*Collision*  link4 / box\n";
  a.report = json::parse(R"({"status": "collision", "line": 4})");
  CHECK(suite::compare(e, a).empty());
}

TEST_CASE("expected files: problems name the file") {
  const fs::path dir = suite_dir("load");
  write(dir / "a.v2", kHello);
  const suite::Case c{"a", dir, "a", suite::CaseKind::expect_json};
  const std::string file = (dir / "a.expect.json").generic_string();
  std::string why;

  write(dir / "a.expect.json", "{\"exit\": 0,\n \"stdout\": \"hi\n}");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why.rfind(file + ": malformed JSON: parse error at line ", 0) == 0);

  write(dir / "a.expect.json", R"({"exit": 0, "stdot": "hi\n"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": unknown key \"stdot\" (known: cell, exit, main, report, stderr_has, stdout)");

  write(dir / "a.expect.json", R"({"stdout": "hi\n"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": \"exit\" is required");

  write(dir / "a.expect.json", R"({"exit": "0"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": \"exit\" must be an integer");

  write(dir / "a.expect.json", R"({"exit": 0, "cell": "c.yaml", "main": "hello", "stderr_has": ["x"],
                                   "report": {"status": "completed"}})");
  const auto e = suite::load_expectation(c, why);
  REQUIRE(e);
  CHECK(suite::run_arguments(c, *e, "/tmp/r.json") ==
        std::vector<std::string>{"run", "a.v2", "--main", "hello", "--cell", "c.yaml", "--report", "/tmp/r.json"});

  fs::remove(dir / "a.v2");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == (dir / "a.v2").generic_string() + ": file not found (every expected file needs its program)");
}

TEST_CASE("NAME.out cases imply exit 0 and Program completed, or exit 2 and NAME.err") {
  const fs::path dir = suite_dir("out");
  write(dir / "a.v2", "; comment\n.program Hello()\n    TYPE \"hi\"\n.END\n");
  write(dir / "a.out", "hi\n");
  const suite::Case c{"a", dir, "a", suite::CaseKind::out_files};
  std::string why;
  auto e = suite::load_expectation(c, why);
  REQUIRE(e);
  CHECK(e->exit == 0);
  CHECK(e->stderr_text == std::string("Program completed: hello\n"));
  write(dir / "a.err", "*Division by zero*\n");
  e = suite::load_expectation(c, why);
  REQUIRE(e);
  CHECK(e->exit == 2);
  CHECK(e->stderr_text == std::string("*Division by zero*\n"));
}

TEST_CASE("discovery: cases under folders and named files, sessions and bare programs skipped") {
  const fs::path dir = suite_dir("discover");
  fs::create_directories(dir / "sub");
  fs::create_directories(dir / ".hidden");
  write(dir / "a.v2", kHello);
  write(dir / "a.out", "hi\n42\n");
  write(dir / "sub" / "b.v2", kHello);
  write(dir / "sub" / "b.expect.json", R"({"exit": 0})");
  write(dir / "lonely.v2", kHello);                        // no expected results: no case
  write(dir / "session.txt", "LOAD a\n");                  // a monitor session, no case
  write(dir / "session.out", "");
  write(dir / ".hidden" / "c.v2", kHello);
  write(dir / ".hidden" / "c.out", "");
  write(dir / "orphan.expect.json", R"({"exit": 0})");     // a case without its program: FAIL later
  write(dir / "prog.out", "\x7f" "ELF");                   // a compiler's output, no case

  auto d = suite::discover({dir.string()});
  CHECK(d.errors.empty());
  std::vector<std::string> names;
  for (const auto& c : d.cases) names.push_back(fs::relative(c.dir / c.stem, dir).generic_string());
  CHECK(names == std::vector<std::string>{"a", "orphan", "sub/b"});
  CHECK(d.cases[0].kind == suite::CaseKind::out_files);
  CHECK(d.cases[2].kind == suite::CaseKind::expect_json);

  d = suite::discover({(dir / "sub" / "b.v2").string(), (dir / "a.out").string()});
  CHECK(d.errors.empty());
  CHECK(d.cases.size() == 2);

  d = suite::discover({(dir / "missing").string(), (dir / "lonely.v2").string(), (dir / "session.out").string(),
                       (dir / "prog.out").string()});
  REQUIRE(d.errors.size() == 4);
  CHECK(d.errors[3] == "*Not a test case*  " + (dir / "prog.out").generic_string() +
                           ": no prog.v2 with prog.expect.json or prog.out beside it");
  CHECK(d.errors[0] == "*File not found*  " + (dir / "missing").string());
  CHECK(d.errors[1].rfind("*Not a test case*  ", 0) == 0);
  CHECK(d.errors[2].find("monitor session") != std::string::npos);

  CHECK(suite::filter_matches("stiff/num", "programs/stiff/num_atan2"));
  CHECK_FALSE(suite::filter_matches("stiff/num", "programs/stiff/long_draw"));
  CHECK(suite::filter_matches("*/demo/c*", "programs/demo/crash"));
  CHECK_FALSE(suite::filter_matches("demo/c*", "programs/demo/crash"));  // a glob matches the whole name
}

TEST_CASE("asimov test: a passing suite exits 0 with one PASS line per case and a summary") {
  const fs::path dir = suite_dir("pass");
  write(dir / "hello.v2", kHello);
  write(dir / "hello.out", "hi\n42\n");
  write(dir / "broken.v2", kBroken);
  write(dir / "broken.expect.json", R"({"exit": 2, "stdout": "", "stderr_has": ["*Division by zero*"],
                                        "report": {"status": "error", "line": 2}})");
  const auto r = run_cli("test " + quoted(dir.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("PASS " + (dir / "broken").string()) != std::string::npos);
  CHECK(r.out.find("PASS " + (dir / "hello").string()) != std::string::npos);
  CHECK(r.out.find("2 passed, 0 failed, 2 cases in ") != std::string::npos);
  CHECK(r.err.empty());
}

TEST_CASE("asimov test: a wrong expectation FAILs with its differences and exit code 4") {
  const fs::path dir = suite_dir("fail");
  write(dir / "hello.v2", kHello);
  write(dir / "hello.expect.json", R"({"exit": 3, "stdout": "hi\n41\n", "stderr_has": ["*Collision*"],
                                       "report": {"status": "collision"}})");
  write(dir / "bad.v2", kHello);
  write(dir / "bad.expect.json", "{\"exit\": 0,}");
  write(dir / "good.v2", kHello);
  write(dir / "good.out", "hi\n42\n");
  const fs::path junit = dir / "results.xml";
  const auto r = run_cli("test " + quoted(dir.string()) + " --junit " + quoted(junit.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);
  CHECK(r.out.find("FAIL " + (dir / "hello").string()) != std::string::npos);
  CHECK(r.out.find("       exit code: expected 3, got 0\n") != std::string::npos);
  CHECK(r.out.find("       stdout line 2: expected \"41\", got \"42\"\n") != std::string::npos);
  CHECK(r.out.find("       stderr: missing \"*Collision*\"\n") != std::string::npos);
  CHECK(r.out.find("       report.status: expected \"collision\", got \"completed\"\n") != std::string::npos);
  CHECK(r.out.find("FAIL " + (dir / "bad").string()) != std::string::npos);
  CHECK(r.out.find((dir / "bad.expect.json").string() + ": malformed JSON: ") != std::string::npos);
  CHECK(r.out.find("PASS " + (dir / "good").string()) != std::string::npos);
  CHECK(r.out.find("1 passed, 2 failed, 3 cases in ") != std::string::npos);

  const std::string xml = slurp(junit);
  CHECK(xml.find("<testsuites name=\"asimov test\" tests=\"3\" failures=\"2\"") != std::string::npos);
  CHECK(xml.find("<failure message=\"exit code: expected 3, got 0\">") != std::string::npos);
  CHECK(xml.find("<testcase name=\"good\"") != std::string::npos);
  for (const auto& entry : fs::directory_iterator(dir))  // written through a rename: no leftovers
    CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);

  // Parallel runs give the same lines in the same order (times aside).
  const auto parallel = run_cli("test -j 2 " + quoted(dir.string()));
  CHECK(parallel.exit_code == 4);
  const auto without_times = [](const std::string& text) {
    std::string kept;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("PASS ", 0) == 0 || line.rfind("FAIL ", 0) == 0) line = line.substr(0, line.find(' ', 5));
      if (line.find(" passed, ") == std::string::npos) kept += line + "\n";
    }
    return kept;
  };
  CHECK(without_times(parallel.out) == without_times(r.out));
}

TEST_CASE("asimov test: usage and file errors exit 1") {
  const fs::path dir = suite_dir("usage");
  auto r = run_cli("test " + quoted((dir / "nowhere").string()));
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*File not found*  " + (dir / "nowhere").string() + "\n");

  r = run_cli("test " + quoted(dir.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("*No test cases*  none under") == 0);

  write(dir / "hello.v2", kHello);
  write(dir / "hello.out", "hi\n42\n");
  r = run_cli("test " + quoted(dir.string()) + " --filter nothing_like_this");
  CHECK(r.exit_code == 1);
  CHECK(r.err == "*No test cases*  none of 1 matches --filter nothing_like_this\n");

  r = run_cli("test " + quoted(dir.string()) + " --junit " + quoted((dir / "no" / "such" / "r.xml").string()));
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("*Cannot write file*") == 0);

  r = run_cli("test " + quoted(dir.string()) + " -j 0");
  CHECK(r.exit_code == 1);
}

TEST_CASE("asimov test: a case running past --timeout is stopped and FAILs") {
  const fs::path dir = suite_dir("timeout");
  // Moves back and forth without end (plain statements would meet the statement limit first).
  write(dir / "spin.v2", ".PROGRAM spin()\n    MOVE TRANS(500, 100, 100, 0, 180, 0)\n    WHILE TRUE DO\n"
                         "        DRAW 1, 0.5, -0.25\n        DRAW -1, -0.5, 0.25\n    END\n.END\n");
  write(dir / "spin.yaml", "robot: puma560\ntool: [0, 0, 200, 0, 0, 0]\ncollision: {enabled: false}\n");
  write(dir / "spin.expect.json", R"({"cell": "spin.yaml", "exit": 0})");
  write(dir / "quick.v2", kHello);
  write(dir / "quick.out", "hi\n42\n");
  const auto r = run_cli("test --timeout 1 " + quoted(dir.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);
  CHECK(r.out.find("FAIL " + (dir / "spin").string()) != std::string::npos);
  CHECK(r.out.find("       run: timed out after 1 s\n") != std::string::npos);
  CHECK(r.out.find("PASS " + (dir / "quick").string()) != std::string::npos);
}

TEST_CASE("asimov test --update rewrites the expected files of failed cases") {
  const fs::path dir = suite_dir("update");
  write(dir / "hello.v2", kHello);
  write(dir / "hello.out", "hello\n");
  write(dir / "hello.err", "*Division by zero*\n");
  write(dir / "broken.v2", kBroken);
  write(dir / "broken.expect.json", R"({"exit": 0, "stdout": "x\n", "report": {"status": "completed",
                                        "line": {"max": 1}}})");
  const auto r = run_cli("test --update " + quoted(dir.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);  // they failed in this run
  CHECK(slurp(dir / "hello.out") == "hi\n42\n");
  CHECK_FALSE(fs::exists(dir / "hello.err"));
  const json updated = json::parse(slurp(dir / "broken.expect.json"));
  CHECK(updated["exit"] == 2);
  CHECK(updated["stdout"] == "");
  CHECK(updated["report"]["status"] == "error");
  CHECK(updated["report"]["line"] == json::parse(R"({"max": 1})"));  // ranges are left to a person
  CHECK(r.out.find("update: left for a person: report.line: expected a number in [-inf, 1], got 2") !=
        std::string::npos);

  // Everything but the range now passes.
  const auto again = run_cli("test " + quoted(dir.string()));
  CHECK(again.exit_code == 4);
  CHECK(again.out.find("PASS " + (dir / "hello").string()) != std::string::npos);
  CHECK(again.out.find("1 passed, 1 failed") != std::string::npos);
}

TEST_CASE("asimov test runs the demo and cell samples of the repository") {
  const auto r = run_cli("test " + asimov::test::source_path("programs/demo") + " " +
                         asimov::test::source_path("programs/cells"));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("5 passed, 0 failed, 5 cases") != std::string::npos);
}
