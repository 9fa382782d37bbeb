// The end-to-end stiff cases of programs/stiff/: NAME.v2 runs through the real `asimov run`
// (its cell named by the expected file, else the built-in default cell) and must give the
// outcome of NAME.expect.json (docs/stiff-cases.md describes the format):
//   "cell": "file.yaml"            optional, relative to programs/stiff/
//   "exit": 3                      the exit code
//   "report": {...}                a subset of the --report JSON; a {"min": a, "max": b} object
//                                  matches a number in [a, b]
//   "stdout": "..."                the exact TYPE output
//   "stderr_has": ["...", ...]     lines that must appear on stderr
// CTest runs one test per case (tests/CMakeLists.txt sets ASIMOV_STIFF_CASE).
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path stiff_dir() { return fs::path(ASIMOV_SOURCE_DIR) / "programs" / "stiff"; }

// Every key of `expected` must be in `actual` with a matching value.
void match_subset(const json& expected, const json& actual, const std::string& where) {
  INFO("at " << where << ": expected " << expected.dump() << ", got " << actual.dump());
  if (expected.is_object() && expected.size() <= 2 && (expected.contains("min") || expected.contains("max"))) {
    REQUIRE(actual.is_number());
    if (expected.contains("min")) CHECK(actual.get<double>() >= expected["min"].get<double>());
    if (expected.contains("max")) CHECK(actual.get<double>() <= expected["max"].get<double>());
    return;
  }
  if (expected.is_object()) {
    REQUIRE(actual.is_object());
    for (const auto& [key, value] : expected.items()) {
      REQUIRE(actual.contains(key));
      match_subset(value, actual[key], where + "." + key);
    }
  } else if (expected.is_array()) {
    REQUIRE(actual.is_array());
    REQUIRE(actual.size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
      match_subset(expected[i], actual[i], where + "[" + std::to_string(i) + "]");
  } else if (expected.is_number() && actual.is_number()) {
    CHECK(actual.get<double>() == expected.get<double>());
  } else {
    CHECK(actual == expected);
  }
}

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

void run_case(const std::string& name) {
  const fs::path program = stiff_dir() / (name + ".v2");
  const fs::path expect_file = stiff_dir() / (name + ".expect.json");
  REQUIRE(fs::exists(program));
  REQUIRE(fs::exists(expect_file));
  const json expect = json::parse(asimov::test::slurp(expect_file));
  const fs::path report = asimov::test::scratch_dir() / ("stiff_" + name + ".json");
  fs::remove(report);
  // Run from programs/stiff/ with relative names, so messages name `NAME.v2:line`.
  fs::current_path(stiff_dir());
  std::string args = "run '" + name + ".v2' --report '" + report.string() + "'";
  if (expect.contains("cell")) args += " --cell '" + expect["cell"].get<std::string>() + "'";
  const auto r = asimov::test::run_cli(args);
  INFO("case " << name << "\nstdout:\n" << r.out << "stderr:\n" << r.err);
  CHECK(r.exit_code == expect.at("exit").get<int>());
  if (expect.contains("stdout")) CHECK(r.out == expect["stdout"].get<std::string>());
  if (expect.contains("stderr_has"))
    for (const auto& line : expect["stderr_has"]) {
      INFO("stderr must contain: " << line.get<std::string>());
      CHECK(r.err.find(line.get<std::string>()) != std::string::npos);
    }
  if (expect.contains("report")) {
    REQUIRE(fs::exists(report));
    const json doc = json::parse(asimov::test::slurp(report));
    match_subset(expect["report"], doc, "report");
    check_finite(doc, "report");
  }
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
