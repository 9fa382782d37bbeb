// Suites of sample programs with expected results (`asimov test`, programs/README.md): finding
// the cases, reading their expected files, running one case as `asimov run` would, and
// comparing. The one matcher: tests/stiff/test_programs.cpp uses it too.
#pragma once
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace asimov::app::suite {

// A case is NAME.v2 with NAME.expect.json (exit, stdout, stderr lines, report fields) or with
// NAME.out (+ NAME.err when the run must stop with an error) beside it.
enum class CaseKind { expect_json, out_files };

struct Case {
  std::string name;             // the .v2 path without extension, as found: programs/demo/crash
  std::filesystem::path dir;    // the folder holding the files; the case runs from here
  std::string stem;             // NAME
  CaseKind kind = CaseKind::expect_json;
  std::filesystem::path file(const std::string& extension) const { return dir / (stem + extension); }
};

struct Discovery {
  std::vector<Case> cases;           // sorted by name, no duplicates
  std::vector<std::string> errors;   // usage/file errors: a PATH that is missing or not a case
};

// Every case under the given directories (recursively) and files (NAME.v2, NAME.expect.json,
// NAME.out or NAME.err name the case NAME).
Discovery discover(const std::vector<std::string>& paths);

// True when `name` is selected by --filter: a substring, or a glob when it has * ? or [.
bool filter_matches(const std::string& pattern, const std::string& name);

struct Expectation {
  int exit = 0;
  std::string cell;                         // --cell, relative to the case folder; empty: built-in
  std::string main;                         // --main; empty: the first program
  std::optional<std::string> stdout_text;   // exact TYPE output
  std::optional<std::string> stderr_text;   // exact stderr (NAME.out cases)
  std::vector<std::string> stderr_has;      // substrings that must appear on stderr
  std::optional<nlohmann::json> report;     // subset of the --report JSON; {"min","max"} ranges
};

// Reads the expected files of a case. On a problem (missing NAME.v2 or NAME.out, malformed
// JSON, unknown key, wrong type) returns nullopt and fills `why` with "FILE: what".
std::optional<Expectation> load_expectation(const Case& c, std::string& why);

struct Actual {
  int exit_code = -1;       // -1 when the run did not exit normally
  std::string exit_note;    // "killed by signal 9", "timed out after 60 s", "cannot start ..."
  std::string out, err;
  std::optional<nlohmann::json> report;  // when a report was asked for and written
  std::string report_problem;            // the report was asked for but is missing or malformed
  double seconds = 0;                    // wall time of the run
};

// The arguments after the executable: run NAME.v2 [--main M] [--cell C] [--report R].
std::vector<std::string> run_arguments(const Case& c, const Expectation& e, const std::filesystem::path& report);

// Runs the case through `executable run ...` in the case folder, stdin from /dev/null, files for
// the outputs under `scratch` (tag keeps parallel runs apart). Thread-safe; kills the run after
// `timeout`.
// `stop` set (Ctrl-C): the case's process is killed and exit_note says "interrupted".
Actual run_case(const Case& c, const Expectation& e, const std::string& executable,
                const std::filesystem::path& scratch, const std::string& tag, std::chrono::seconds timeout,
                const std::atomic<bool>* stop = nullptr);

// Every difference between expected and actual, one short line each; empty: the case passed.
std::vector<std::string> compare(const Expectation& e, const Actual& a);

// The report matcher: every key of `expected` must be in `actual` with a matching value; an
// object whose keys are only "min"/"max" matches a number in that closed range; arrays must have
// the same length; numbers compare as doubles. Appends "path: expected X, got Y" lines.
void match_report(const nlohmann::json& expected, const nlohmann::json& actual, const std::string& path,
                  std::vector<std::string>& diffs);

// "label line N: expected "x", got "y"" for the first differing line, nullopt when equal.
std::optional<std::string> first_line_difference(const std::string& label, const std::string& expected,
                                                 const std::string& actual);

// --update: rewrites the expected files of a failed case from the actual results, as far as the
// format allows. Returns what it did or could not do, one line each.
std::vector<std::string> update_expectation(const Case& c, const Expectation& e, const Actual& a);


}  // namespace asimov::app::suite
