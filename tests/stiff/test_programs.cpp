// The end-to-end stiff cases of programs/stiff/: NAME.v2 runs through the real `asimov run`
// (its cell named by the expected file, else the built-in default cell) and must give the
// outcome of NAME.expect.json (docs/stiff-cases.md describes the format; the matcher is the one
// of `asimov test`, app/suite.hpp):
//   "cell": "file.yaml"            optional, relative to programs/stiff/
//   "exit": 3                      the exit code
//   "report": {...}                a subset of the --report JSON; a {"min": a, "max": b} object
//                                  matches a number in [a, b]
//   "stdout": "..."                the exact TYPE output
//   "stderr_has": ["...", ...]     lines that must appear on stderr
// CTest runs one test per case (tests/CMakeLists.txt sets ASIMOV_STIFF_CASE).
#include "app/suite.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path stiff_dir() { return fs::path(ASIMOV_SOURCE_DIR) / "programs" / "stiff"; }

// No NaN or infinity anywhere in a report. nlohmann writes a non-finite double as null, so null
// counts as non-finite too, except where the schema uses it for "not applicable" (README:
// accuracy.contact_bracket_s is null when the run had no contact).
void check_finite(const json& j, const std::string& where) {
  INFO(where);
  if (where.ends_with(".accuracy.contact_bracket_s")) return;
  CHECK_FALSE(j.is_null());
  if (j.is_number_float()) CHECK(std::isfinite(j.get<double>()));
  if (j.is_structured())
    for (const auto& [key, value] : j.items()) check_finite(value, where + "." + key);
}

// The same matcher as `asimov test` (app/suite.hpp), plus the stiff rule that no report holds a
// NaN or an infinity.
void run_case(const std::string& name) {
  namespace suite = asimov::app::suite;
  const suite::Case c{"programs/stiff/" + name, stiff_dir(), name, suite::CaseKind::expect_json};
  REQUIRE(fs::exists(c.file(".v2")));
  REQUIRE(fs::exists(c.file(".expect.json")));
  std::string why;
  const auto expect = suite::load_expectation(c, why);
  INFO(why);
  REQUIRE(expect);
  // Runs in programs/stiff/ with relative names, so messages name `NAME.v2:line`.
  const auto actual = suite::run_case(c, *expect, ASIMOV_BINARY, asimov::test::scratch_dir(), "stiff_" + name,
                                      std::chrono::seconds(600));
  const auto diffs = suite::compare(*expect, actual);
  std::string listed;
  for (const auto& d : diffs) listed += d + "\n";
  INFO("case " << name << "\n" << listed << "stdout:\n" << actual.out << "stderr:\n" << actual.err);
  CHECK(diffs.empty());
  if (actual.report) check_finite(*actual.report, "report");
}

std::vector<std::string> case_names() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(stiff_dir()))
    if (entry.path().extension() == ".v2") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

// Hidden: CTest runs it once per case with ASIMOV_STIFF_CASE set; without it, every case.
TEST_CASE("stiff program", "[.][stiff]") {
  if (const char* one = std::getenv("ASIMOV_STIFF_CASE")) {
    run_case(one);
    return;
  }
  for (const std::string& name : case_names()) {
    SECTION(name) { run_case(name); }
  }
}

TEST_CASE("every stiff program has its expected outcome and every expected file its program", "[stiff]") {
  const auto names = case_names();
  CHECK(names.size() >= 20);
  for (const auto& name : names) {
    INFO(name);
    CHECK(fs::exists(stiff_dir() / (name + ".expect.json")));
  }
  for (const auto& entry : fs::directory_iterator(stiff_dir())) {
    const std::string file = entry.path().filename().string();
    const auto pos = file.find(".expect.json");
    if (pos == std::string::npos) continue;
    INFO(file);
    CHECK(fs::exists(stiff_dir() / (file.substr(0, pos) + ".v2")));
  }
}
