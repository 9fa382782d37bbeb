// A PUMA 560 cell without objects, an interpreter writing TYPE output to a string.
#pragma once
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/monitor.hpp"
#include "asimov/robots/puma560.hpp"

#include <catch2/catch.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace asimov::test {

inline motion::Cell empty_puma_cell() {
  motion::Cell cell;
  cell.robot = robots::puma560();
  cell.start_joints = robots::JointVector::Zero(6);
  cell.start_joints << 0, -90, 90, 0, 0, 0;  // READY
  return cell;
}

struct InterpreterFixture {
  motion::Simulator sim{empty_puma_cell()};
  std::ostringstream out;
  interpreter::Interpreter interp{sim, out};

  // Loads `text` as "test.v2"; returns the diagnostics.
  std::vector<interpreter::Diagnostic> load(const std::string& text) { return interp.load_source(text, "test.v2"); }

  // Loads and runs `main`; a load error (not a warning) fails the test through `loaded`.
  interpreter::RunResult run(const std::string& text, const std::string& main = "main") {
    const auto diags = load(text);
    loaded = true;
    for (const auto& d : diags) {
      load_report += interpreter::format_diagnostic(d);
      loaded = loaded && d.warning;
    }
    if (!loaded) return {};
    return interp.run(main);
  }

  bool loaded = false;
  std::string load_report;
};

// Runs `text`'s main: its TYPE output, then "ERROR message detail" when an error stopped it.
inline std::string outcome_of(InterpreterFixture& f, const std::string& text) {
  const auto r = f.run(text);
  INFO(f.load_report);
  REQUIRE(f.loaded);
  if (r.status == interpreter::RunStatus::error) return f.out.str() + "ERROR " + r.error.message + " " + r.error.detail;
  REQUIRE(r.status == interpreter::RunStatus::completed);
  return f.out.str();
}

// The same with a monitor over it; run() executes one command line and returns its output.
struct MonitorFixture : InterpreterFixture {
  interpreter::Monitor monitor{interp, sim, out};
  std::string run(const std::string& line) {
    out.str("");
    monitor.execute(line);
    return out.str();
  }
};

// Loads `programs`, runs `main`, requires that it completes and returns its TYPE output.
inline std::string output_of_programs(const std::string& programs) {
  InterpreterFixture f;
  const auto r = f.run(programs);
  INFO(f.load_report);
  REQUIRE(f.loaded);
  INFO(interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == interpreter::RunStatus::completed);
  return f.out.str();
}

}  // namespace asimov::test
