// `asimov test` (app/suite.hpp, app/cmd_test.cpp): the matcher and its messages, the expected
// file, discovery, and the command end to end on small suites written to a scratch folder. The
// repository's own samples run as the CTest tests "programs: FOLDER" (tests/CMakeLists.txt).
#include "app/suite.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
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
const char* kHelloExpect = R"({"exit": 0, "stdout": ["hi", "42"], "stderr": ["Program completed: hello"]})";
const char* kBroken = ".PROGRAM broken()\n    TYPE 1 / 0\n.END\n";

std::vector<std::string> report_diffs(const json& expected, const json& actual) {
  std::vector<std::string> diffs;
  suite::match_report(expected, actual, "report", diffs);
  return diffs;
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// The indented difference lines printed under the FAIL line of case `name`.
std::vector<std::string> diffs_of(const std::string& out, const fs::path& name) {
  std::istringstream in(out);
  std::vector<std::string> diffs;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("PASS ", 0) == 0 || line.rfind("FAIL ", 0) == 0)
      inside = line.rfind("FAIL " + name.string() + " ", 0) == 0;
    else if (inside && line.rfind("       ", 0) == 0)
      diffs.push_back(line.substr(7));
  }
  return diffs;
}

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

TEST_CASE("first differing line of an output, the wall times of a STATUS line are not compared") {
  CHECK_FALSE(suite::first_line_difference("stdout", "a\nb\n", "a\nb\n"));
  CHECK(suite::first_line_difference("stdout", "a\nb\nc\n", "a\nx\nc\n") ==
        std::string("stdout line 2: expected \"b\", got \"x\""));
  CHECK(suite::first_line_difference("stdout", "a\nb\n", "a\n") ==
        std::string("stdout line 2: expected \"b\", got end of output"));
  CHECK(suite::first_line_difference("stderr", "", "oops\n") ==
        std::string("stderr line 1: expected end of output, got \"oops\""));
  CHECK(suite::first_line_difference("stdout", "a\n", "a") == std::string("stdout: expected a final newline"));

  const std::string status = "Accuracy: step <= 229 mm, contact bracket none; wall parse 0.000 s, motion 0.001 s\n";
  CHECK_FALSE(suite::first_line_difference("stdout", "x\n" + status,
                                           "x\nAccuracy: step <= 229 mm, contact bracket none; wall parse 0.004 s\n"));
  CHECK(suite::first_line_difference("stdout", status, "Accuracy: step <= 230 mm, contact bracket none; wall x\n") ==
        std::string("stdout line 1: expected \"Accuracy: step <= 229 mm, contact bracket none; wall parse 0.000 s, "
                    "motion 0.001 s\", got \"Accuracy: step <= 230 mm, contact bracket none; wall x\""));
  // Only a STATUS line has wall times.
  CHECK(suite::first_line_difference("stdout", "at 1; wall 2\n", "at 1; wall 3\n"));
}

TEST_CASE("compare lists exit code, stdout, stderr and report differences, and a NaN in the report") {
  suite::Expectation e;
  e.exit = 3;
  e.stdout_text = "hi\n";
  e.stderr_text = "*Collision*  link4 / box\n";
  e.stderr_has = {"*Collision*"};
  e.report = json::parse(R"({"status": "collision"})");
  suite::Actual a;
  a.exit_code = 0;
  a.out = "ho\n";
  a.err = "Program completed: x\n";
  a.report_problem = "no report was written";
  const auto d = suite::compare(e, a);
  REQUIRE(d.size() == 5);
  CHECK(d[0] == "exit code: expected 3, got 0");
  CHECK(d[1] == "stdout line 1: expected \"hi\", got \"ho\"");
  CHECK(d[2] == "stderr line 1: expected \"*Collision*  link4 / box\", got \"Program completed: x\"");
  CHECK(d[3] == "stderr: missing \"*Collision*\"");
  CHECK(d[4] == "report: no report was written");

  a.exit_code = 3;
  a.out = "hi\n";
  a.err = "*Collision*  link4 / box\n";
  a.report = json::parse(R"({"status": "collision", "line": 4, "accuracy": {"contact_bracket_s": null}})");
  CHECK(suite::compare(e, a).empty());  // contact_bracket_s is null by design when nothing touched

  // nlohmann writes a NaN or an infinity as null: anywhere else it fails the case.
  a.report = json::parse(R"({"status": "collision", "collision": {"time_s": null}, "joints": [1, null]})");
  const auto nan = suite::compare(e, a);
  REQUIRE(nan.size() == 2);
  CHECK(nan[0] == "report.collision.time_s: null (a NaN or an infinity)");
  CHECK(nan[1] == "report.joints[1]: null (a NaN or an infinity)");
}

TEST_CASE("the expected file: problems name the file") {
  const fs::path dir = suite_dir("load");
  write(dir / "a.v2", kHello);
  const suite::Case c{"a", dir, "a", suite::CaseKind::program};
  const std::string file = (dir / "a.expect.json").generic_string();
  std::string why;

  write(dir / "a.expect.json", "{\"exit\": 0,\n \"stdout\": \"hi\n}");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why.rfind(file + ": malformed JSON: parse error at line ", 0) == 0);

  write(dir / "a.expect.json", R"({"exit": 0, "stdot": "hi\n"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": unknown key \"stdot\" (known: args, cell, exit, main, report, stderr, stderr_has, stdout)");

  write(dir / "a.expect.json", R"({"stdout": "hi\n"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": \"exit\" is required");

  write(dir / "a.expect.json", R"({"exit": "0"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": \"exit\" must be an integer");

  write(dir / "a.expect.json", R"({"exit": 0, "stdout": ["hi", 42]})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": \"stdout\" must be a string or an array of lines");

  write(dir / "a.expect.json", R"({"exit": 0, "args": "--strict"})");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == file + ": \"args\" must be an array of strings");

  // An array of lines is the text with a newline after each; a string is the text as it is.
  write(dir / "a.expect.json", R"({"exit": 0, "cell": "c.yaml", "main": "hello", "args": ["--trace", "t.json"],
                                   "stdout": ["hi", "42"], "stderr": "no newline", "stderr_has": ["x"],
                                   "report": {"status": "completed"}})");
  auto e = suite::load_expectation(c, why);
  REQUIRE(e);
  CHECK(e->stdout_text == std::string("hi\n42\n"));
  CHECK(e->stderr_text == std::string("no newline"));
  CHECK(suite::run_arguments(c, *e, "/tmp/r.json") ==
        std::vector<std::string>{"run", "a.v2", "--main", "hello", "--cell", "c.yaml", "--trace", "t.json",
                                 "--report", "/tmp/r.json"});
  write(dir / "a.expect.json", R"({"exit": 0, "stdout": []})");
  e = suite::load_expectation(c, why);
  REQUIRE(e);
  CHECK(e->stdout_text == std::string());

  fs::remove(dir / "a.v2");
  CHECK_FALSE(suite::load_expectation(c, why));
  CHECK(why == (dir / "a.v2").generic_string() + ": file not found (NAME.expect.json needs NAME.v2 or NAME.session beside it)");

  // A session runs `asimov monitor`: no --main, no report, a cell made absolute (it runs in a copy).
  write(dir / "s.session", "WHERE\n");
  const suite::Case s{"s", dir, "s", suite::CaseKind::session};
  CHECK_FALSE(suite::load_expectation(s, why));
  CHECK(why == (dir / "s.expect.json").generic_string() + ": file not found (every case needs one)");
  write(dir / "s.expect.json", R"({"exit": 0, "report": {"status": "completed"}})");
  CHECK_FALSE(suite::load_expectation(s, why));
  CHECK(why == (dir / "s.expect.json").generic_string() + ": \"report\" is for programs (asimov run), not monitor sessions");
  write(dir / "s.expect.json", R"({"exit": 2, "cell": "c.yaml", "args": ["--strict", "a.v2"]})");
  e = suite::load_expectation(s, why);
  REQUIRE(e);
  CHECK(suite::run_arguments(s, *e, "") ==
        std::vector<std::string>{"monitor", "--cell", fs::absolute(dir / "c.yaml").string(), "--strict", "a.v2"});
}

TEST_CASE("discovery: cases under folders and named files, programs without an expected file skipped") {
  const fs::path dir = suite_dir("discover");
  fs::create_directories(dir / "sub");
  fs::create_directories(dir / ".hidden");
  write(dir / "a.v2", kHello);
  write(dir / "a.expect.json", kHelloExpect);
  write(dir / "sub" / "b.v2", kHello);
  write(dir / "sub" / "b.expect.json", R"({"exit": 0})");
  write(dir / "lonely.v2", kHello);                        // no expected file: no case (a session may load it)
  write(dir / "session.session", "LOAD a\n");              // a session is a case (it FAILs without its JSON)
  write(dir / "resume.v2", kHello);                        // a session may share its name with a program
  write(dir / "resume.session", "LOAD resume\n");
  write(dir / "resume.expect.json", R"({"exit": 0})");
  write(dir / ".hidden" / "c.v2", kHello);
  write(dir / ".hidden" / "c.expect.json", R"({"exit": 0})");
  write(dir / "orphan.expect.json", R"({"exit": 0})");     // a case without its program: FAIL later
  write(dir / "a.out", "\x7f" "ELF");                      // a compiler's output, no case

  auto d = suite::discover({dir.string()});
  CHECK(d.errors.empty());
  std::vector<std::string> names;
  for (const auto& c : d.cases) names.push_back(fs::relative(c.dir / c.stem, dir).generic_string());
  CHECK(names == std::vector<std::string>{"a", "orphan", "resume", "session", "sub/b"});
  CHECK(d.cases[0].kind == suite::CaseKind::program);
  CHECK(d.cases[2].kind == suite::CaseKind::session);
  CHECK(d.cases[3].kind == suite::CaseKind::session);

  d = suite::discover({(dir / "sub" / "b.v2").string(), (dir / "a.expect.json").string(),
                       (dir / "resume.v2").string()});
  CHECK(d.errors.empty());
  CHECK(d.cases.size() == 3);

  d = suite::discover({(dir / "missing").string(), (dir / "lonely.v2").string(), (dir / "a.out").string()});
  REQUIRE(d.errors.size() == 3);
  CHECK(d.errors[0] == "*File not found*  " + (dir / "missing").string());
  CHECK(d.errors[1] == "*Not a test case*  " + (dir / "lonely.v2").generic_string() +
                           ": no lonely.expect.json beside it");
  CHECK(d.errors[2] == "*Not a test case*  " + (dir / "a.out").string() +
                           ": expected NAME.v2, NAME.session or NAME.expect.json");

  CHECK(suite::filter_matches("stiff/num", "programs/stiff/num_atan2"));
  CHECK_FALSE(suite::filter_matches("stiff/num", "programs/stiff/long_draw"));
  CHECK(suite::filter_matches("*/demo/c*", "programs/demo/crash"));
  CHECK_FALSE(suite::filter_matches("demo/c*", "programs/demo/crash"));  // a glob matches the whole name
}

TEST_CASE("asimov test: a passing suite exits 0 with one PASS line per case and a summary") {
  const fs::path dir = suite_dir("pass");
  write(dir / "hello.v2", kHello);
  write(dir / "hello.expect.json", kHelloExpect);
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

// One passing program and one passing session, then one copy of each per kind of assertion with
// that one value wrong: each must FAIL with exactly its own difference.
TEST_CASE("asimov test: a wrong expectation of each kind FAILs with its difference") {
  const fs::path dir = suite_dir("kinds");
  write(dir / "c.yaml", "robot: puma560\ntool: [0, 0, 200, 0, 0, 0]\ncollision: {enabled: false}\n");
  const std::string two = ".PROGRAM first()\n    TYPE \"first\"\n.END\n"
                          ".PROGRAM second()\n    TYPE \"second\"\n    MOVE TRANS(500, 100, 100, 0, 180, 0)\n.END\n";
  const json good = json::parse(R"({"exit": 0, "cell": "c.yaml", "main": "second", "stdout": ["second"],
      "stderr": ["Program completed: second"], "stderr_has": ["completed"],
      "report": {"status": "completed", "program": "second", "poses_checked": {"min": 1},
                 "accuracy": {"motions": 1}}})");
  const json good_session =
      json::parse(R"({"exit": 0, "args": ["two.v2"], "stdout": ["first", "Program completed: first"], "stderr": []})");
  struct Wrong {
    const char* name;
    bool session;
    json patch;  // merged into the good expectation
    std::string diff;
  };
  const std::vector<Wrong> wrongs = {
      {"exit", false, {{"exit", 2}}, "exit code: expected 2, got 0"},
      {"stdout_text", false, {{"stdout", "secnd\n"}}, "stdout line 1: expected \"secnd\", got \"second\""},
      {"stdout_lines", false, {{"stdout", {"second", "more"}}}, "stdout line 2: expected \"more\", got end of output"},
      {"stdout_newline", false, {{"stdout", "second"}}, "stdout: expected no final newline"},
      {"stderr", false, {{"stderr", {"Program completed: first"}}},
       "stderr line 1: expected \"Program completed: first\", got \"Program completed: second\""},
      {"stderr_has", false, {{"stderr_has", {"completed", "*Collision*"}}}, "stderr: missing \"*Collision*\""},
      {"report_value", false, {{"report", {{"status", "error"}}}}, "report.status: expected \"error\", got \"completed\""},
      {"report_range", false, {{"report", {{"poses_checked", {{"min", 1}, {"max", 10}}}}}},
       "report.poses_checked: expected a number in [1, 10], got "},
      {"report_nested", false, {{"report", {{"accuracy", {{"motions", 2}}}}}},
       "report.accuracy.motions: expected 2, got 1"},
      {"report_missing", false, {{"report", {{"nosuch", 1}}}}, "report.nosuch: missing, expected 1"},
      {"main", false, {{"main", "first"}}, "stdout line 1: expected \"second\", got \"first\""},
      {"cell", false, {{"cell", "nocell.yaml"}}, "exit code: expected 0, got 1"},
      {"args", false, {{"args", {"--no-such-option"}}}, "exit code: expected 0, got 1"},
      {"session_exit", true, {{"exit", 2}}, "exit code: expected 2, got 0"},
      {"session_stdout", true, {{"stdout", {"second"}}}, "stdout line 1: expected \"second\", got \"first\""},
      {"session_stderr", true, {{"stderr", {"oops"}}}, "stderr line 1: expected \"oops\", got end of output"},
      {"session_args", true, {{"args", json::array()}}, "stdout line 1: expected \"first\", got "},
  };
  write(dir / "good.v2", two);
  write(dir / "good.expect.json", good.dump());
  write(dir / "two.v2", two);  // the program the sessions load
  write(dir / "session.session", "EXECUTE first\n");
  write(dir / "session.expect.json", good_session.dump());
  for (const auto& w : wrongs) {
    json e = w.session ? good_session : good;
    e.merge_patch(w.patch);
    if (w.session) write(dir / (std::string(w.name) + ".session"), "EXECUTE first\n");
    else write(dir / (std::string(w.name) + ".v2"), two);
    write(dir / (std::string(w.name) + ".expect.json"), e.dump());
  }
  const auto r = run_cli("test -j 2 " + quoted(dir.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);
  CHECK(r.out.find("PASS " + (dir / "good").string() + " ") != std::string::npos);
  CHECK(r.out.find("PASS " + (dir / "session").string() + " ") != std::string::npos);
  CHECK(r.out.find("2 passed, " + std::to_string(wrongs.size()) + " failed, ") != std::string::npos);
  for (const auto& w : wrongs) {
    INFO(w.name);
    CHECK(r.out.find("FAIL " + (dir / w.name).string() + " ") != std::string::npos);
    const auto diffs = diffs_of(r.out, dir / w.name);
    CHECK(std::any_of(diffs.begin(), diffs.end(), [&](const std::string& d) { return d.rfind(w.diff, 0) == 0; }));
  }
}

TEST_CASE("asimov test: unusable expected files FAIL and the others still run, JUnit, -j keeps the order") {
  const fs::path dir = suite_dir("fail");
  write(dir / "hello.v2", kHello);
  write(dir / "hello.expect.json", R"({"exit": 3, "stdout": "hi\n41\n"})");
  write(dir / "bad.v2", kHello);
  write(dir / "bad.expect.json", "{\"exit\": 0,}");
  write(dir / "good.v2", kHello);
  write(dir / "good.expect.json", kHelloExpect);
  const fs::path junit = dir / "results.xml";
  const auto r = run_cli("test " + quoted(dir.string()) + " --junit " + quoted(junit.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);
  CHECK(r.out.find("FAIL " + (dir / "hello").string()) != std::string::npos);
  CHECK(r.out.find("       exit code: expected 3, got 0\n") != std::string::npos);
  CHECK(r.out.find("       stdout line 2: expected \"41\", got \"42\"\n") != std::string::npos);
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

TEST_CASE("asimov test: a session runs in a copy of its folder, links followed, so STORE leaves the sources alone") {
  const fs::path dir = suite_dir("session");
  fs::create_directories(dir / "other");
  write(dir / "other" / "hello.v2", kHello);
  fs::create_symlink("other/hello.v2", dir / "hello.v2");
  write(dir / "store.session", "; a comment line is silent\nLOAD hello\nSTORE saved\nEXECUTE hello\n");
  write(dir / "store.expect.json", R"({"exit": 0, "stdout": ["hi", "42", "Program completed: hello"], "stderr": ""})");
  const auto r = run_cli("test " + quoted((dir / "store.session").string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("PASS " + (dir / "store").string()) != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "saved.v2"));
  CHECK(fs::is_symlink(dir / "hello.v2"));
}

TEST_CASE("asimov test: a program case's files are a copy of its folder, so a case that writes passes every time") {
  const fs::path dir = suite_dir("files-copy");
  fs::create_directories(dir / "data");
  write(dir / "data" / "in.txt", "7\n");
  // Appends a line to log.txt (created the first time) and counts its lines; reads data/in.txt.
  write(dir / "append.v2",
        ".PROGRAM append()\n    ATTACH (lun, 4) \"DISK\"\n    FOPENA (lun) \"log.txt\"\n    WRITE (lun) \"x\"\n"
        "    FCLOSE (lun)\n    FOPENR (lun) \"log.txt\"\n    n = 0\n    READ (lun) $l\n    WHILE IOSTAT(lun) >= 0 DO\n"
        "        n = n + 1\n        READ (lun) $l\n    END\n    FCLOSE (lun)\n    FOPENR (lun) \"data/in.txt\"\n"
        "    READ (lun) v\n    FCLOSE (lun)\n    DETACH (lun)\n    TYPE \"lines \", n, \" value \", v\n.END\n");
  write(dir / "append.expect.json", R"({"exit": 0, "stdout": ["lines 1 value 7"], "stderr": ["Program completed: append"]})");
  for (int run = 1; run <= 2; ++run) {
    const auto r = run_cli("test " + quoted(dir.string()));
    INFO(run << ": " << r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK_FALSE(fs::exists(dir / "log.txt"));
  }
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
  write(dir / "hello.expect.json", kHelloExpect);
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
  write(dir / "quick.expect.json", kHelloExpect);
  const auto r = run_cli("test --timeout 1 " + quoted(dir.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);
  CHECK(r.out.find("FAIL " + (dir / "spin").string()) != std::string::npos);
  CHECK(r.out.find("       run: timed out after 1 s\n") != std::string::npos);
  CHECK(r.out.find("PASS " + (dir / "quick").string()) != std::string::npos);
}

TEST_CASE("asimov test --update rewrites the exact values of failed cases, keeping the form of each") {
  const fs::path dir = suite_dir("update");
  write(dir / "hello.v2", kHello);
  write(dir / "hello.expect.json", R"({"exit": 2, "stdout": ["hello"], "stderr": "*Division by zero*\n"})");
  write(dir / "broken.v2", kBroken);
  write(dir / "broken.expect.json", R"({"exit": 0, "stdout": "x\n", "stderr_has": ["Program completed"],
                                        "report": {"status": "completed", "line": {"max": 1}}})");
  write(dir / "two.v2", kHello);
  write(dir / "session.session", "LOAD two\nEXECUTE hello\n");
  write(dir / "session.expect.json", R"({"exit": 2, "stdout": ["hello"], "stderr": []})");
  const auto r = run_cli("test --update " + quoted(dir.string()));
  INFO(r.out << r.err);
  CHECK(r.exit_code == 4);  // they failed in this run
  const json hello = json::parse(slurp(dir / "hello.expect.json"));
  CHECK(hello == json::parse(R"({"exit": 0, "stdout": ["hi", "42"], "stderr": "Program completed: hello\n"})"));
  const json broken = json::parse(slurp(dir / "broken.expect.json"));
  CHECK(broken["exit"] == 2);
  CHECK(broken["stdout"] == "");
  CHECK(broken["report"]["status"] == "error");
  CHECK(broken["report"]["line"] == json::parse(R"({"max": 1})"));  // ranges and lines are left to a person
  CHECK(broken["stderr_has"] == json::parse(R"(["Program completed"])"));
  CHECK(r.out.find("update: left for a person: report.line: expected a number in [-inf, 1], got 2") !=
        std::string::npos);
  CHECK(r.out.find("update: left for a person: stderr line \"Program completed\"") != std::string::npos);
  CHECK(r.out.find("update: wrote " + (dir / "hello.expect.json").generic_string()) != std::string::npos);
  const json session = json::parse(slurp(dir / "session.expect.json"));
  CHECK(session["exit"] == 0);
  CHECK(session["stdout"] == json::parse(R"(["hi", "42", "Program completed: hello"])"));
  CHECK(session["stderr"] == json::array());

  // Everything but the range and the stderr line now passes.
  const auto again = run_cli("test " + quoted(dir.string()));
  CHECK(again.exit_code == 4);
  CHECK(again.out.find("PASS " + (dir / "hello").string()) != std::string::npos);
  CHECK(again.out.find("PASS " + (dir / "session").string()) != std::string::npos);
  CHECK(again.out.find("2 passed, 1 failed") != std::string::npos);
}

// Every program of programs/ is a case, except in programs/monitor, where sessions load them;
// every case folder is a CTest test "programs: FOLDER" (tests/CMakeLists.txt). Expected files
// of the old formats (NAME.out, NAME.err, a session NAME.txt) would be silently skipped.
TEST_CASE("every sample program outside programs/monitor has its NAME.expect.json, and no old format is left") {
  std::size_t programs = 0;
  for (const auto& entry : fs::recursive_directory_iterator(asimov::test::source_path("programs"))) {
    const fs::path p = entry.path();
    INFO(p.string());
    CHECK(p.extension() != ".out");
    CHECK(p.extension() != ".err");
    CHECK(p.extension() != ".txt");
    if (p.extension() != ".v2" || p.parent_path().filename() == "monitor") continue;
    ++programs;
    CHECK(fs::exists(fs::path(p).replace_extension(".expect.json")));
  }
  CHECK(programs >= 90);
}
