// Suites of sample programs with expected results (`asimov test`, programs/README.md): finding
// the cases, reading their NAME.expect.json, running one case as a user would, and comparing.
// The one runner of the repository's samples: CTest calls `asimov test programs/FOLDER`.
#pragma once
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace asimov::app::suite {

// A case is NAME.expect.json beside NAME.session (a monitor session: `asimov monitor` with the
// script on stdin) or else beside NAME.v2 (a program: `asimov run NAME.v2`).
enum class CaseKind { program, session };

struct Case {
  std::string name;             // the path without extension, as found: programs/demo/crash
  std::filesystem::path dir;    // the folder holding the files
  std::string stem;             // NAME
  CaseKind kind = CaseKind::program;
  std::filesystem::path file(const std::string& extension) const { return dir / (stem + extension); }
};

struct Discovery {
  std::vector<Case> cases;           // sorted by name, no duplicates
  std::vector<std::string> errors;   // usage/file errors: a PATH that is missing or not a case
};

// Every case under the given directories (recursively, hidden folders skipped) and files
// (NAME.v2, NAME.session or NAME.expect.json name the case NAME).
Discovery discover(const std::vector<std::string>& paths);

// True when `name` is selected by --filter: a substring, or a glob when it has * ? or [.
bool filter_matches(const std::string& pattern, const std::string& name);

struct Expectation {
  int exit = 0;
  std::string cell;                         // --cell, relative to the case folder; empty: built-in
  std::string main;                         // --main (programs); empty: the first program
  std::vector<std::string> args;            // further arguments of `run` or `monitor`
  std::optional<std::string> stdout_text;   // exact stdout
  std::optional<std::string> stderr_text;   // exact stderr
  std::vector<std::string> stderr_has;      // substrings that must appear on stderr
  std::optional<nlohmann::json> report;     // subset of the --report JSON; {"min","max"} ranges
};

// Reads NAME.expect.json. On a problem (missing NAME.v2/NAME.session, malformed JSON, unknown
// key, wrong type) returns nullopt and fills `why` with "FILE: what".
std::optional<Expectation> load_expectation(const Case& c, std::string& why);

struct Actual {
  int exit_code = -1;       // -1 when the run did not exit normally
  std::string exit_note;    // "killed by signal 9", "timed out after 60 s", "cannot start ..."
  std::string out, err;
  std::optional<nlohmann::json> report;  // when a report was asked for and written
  std::string report_problem;            // the report was asked for but is missing or malformed
  double seconds = 0;                    // wall time of the run
};

// The arguments after the executable. A program: run NAME.v2 [--main M] [--cell C] [ARGS]
// [--report R], run from the case folder. A session: monitor [--cell C] [ARGS], run from a
// scratch copy of the case folder, so C is made absolute.
std::vector<std::string> run_arguments(const Case& c, const Expectation& e, const std::filesystem::path& report);

// Runs the case: a program in its folder with stdin from /dev/null, a session in a fresh copy
// of its folder (under `scratch`) with NAME.session on stdin, so STORE never writes into the
// sources. Outputs go to files under `scratch` (tag keeps parallel runs apart). Thread-safe;
// kills the run after `timeout`, or when `stop` is set (Ctrl-C; exit_note says "interrupted").
Actual run_case(const Case& c, const Expectation& e, const std::string& executable,
                const std::filesystem::path& scratch, const std::string& tag, std::chrono::seconds timeout,
                const std::atomic<bool>* stop = nullptr);

// Every difference between expected and actual, one short line each; empty: the case passed.
// Beyond the expectation, a report may hold no NaN or infinity (written as null).
std::vector<std::string> compare(const Expectation& e, const Actual& a);

// The report matcher: every key of `expected` must be in `actual` with a matching value; an
// object whose keys are only "min"/"max" matches a number in that closed range; arrays must have
// the same length; numbers compare as doubles. Appends "path: expected X, got Y" lines.
void match_report(const nlohmann::json& expected, const nlohmann::json& actual, const std::string& path,
                  std::vector<std::string>& diffs);

// "label line N: expected "x", got "y"" for the first differing line, nullopt when equal. The
// wall-clock tail of a monitor STATUS line ("Accuracy: ...; wall ...") is not compared.
std::optional<std::string> first_line_difference(const std::string& label, const std::string& expected,
                                                 const std::string& actual);

// --update: rewrites the exact values of a failed case's NAME.expect.json from the actual run.
// Returns what it did or could not do, one line each.
std::vector<std::string> update_expectation(const Case& c, const Expectation& e, const Actual& a);

}  // namespace asimov::app::suite
