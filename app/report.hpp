// The --report and --trace JSON documents of `asimov run` (schema in README.md).
#pragma once
#include "asimov/core/result.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include <nlohmann/json.hpp>
#include <string>

namespace asimov::app {

// "schema_version" of every JSON document asimov writes (report, trace, replay data, test
// results); docs/schema/*.schema.json. Raised when a field changes meaning or goes away.
constexpr int kSchemaVersion = 1;

struct RunSummary {
  std::string file;                 // the .v2 file run
  interpreter::RunResult result;
  double sim_time_s = 0;
  std::uint64_t poses_checked = 0;
  collision::StepCounts counts;     // summed over every checked pose
  bool engine_used = false;         // false when the cell has no enabled pair
  std::uint64_t bisection_checks = 0;  // poses checked by contact-time bisection (not in poses_checked)
  motion::Stepping stepping = motion::Stepping::fixed;
  motion::RunAccuracy accuracy;
  motion::RunTiming timing;
  double wall_s = 0;                // whole command: cell load to the end of the run
  nlohmann::json workcell;          // "events" and "parts" (workcell_json); null: a static cell
  nlohmann::json clearance;         // the clearance report (clearance_json)
  std::string closest;              // interpreter::format_closest: "" when no pair came near
};

// The report's "clearance" object (docs/collision.md §12): report_within_mm, clearance_mm,
// on_clearance, and per pair that came nearer than report_within_mm (or clearance_mm) its least
// distance, time, step, program and line, witness points, nearest first; "closest": the first.
nlohmann::json clearance_json(const motion::Simulator& sim, const std::vector<interpreter::MotionStep>& motions);

// The summary of a run that ended with `result` on `sim` (clock, counts, accuracy, timing);
// `wall_s`: the whole command so far. `asimov run` and the Python module report through it.
RunSummary summarize_run(const std::string& file, interpreter::RunResult result, const motion::Simulator& sim,
                         double wall_s);

// The reacting cell's part of the report: "events" (time, kind, subject, detail, line) and
// "parts" (name, state, final pose).
nlohmann::json workcell_json(const motion::CellRuntime& cell);
// Shared with the replay page (app/replay.cpp): a part's state as the report names it
// ("resting", "on_conveyor", "carried", "removed") and one event of the cell.
const char* part_state_name(motion::Holder h);
nlohmann::json event_json(const motion::CellEvent& e);

// The "accuracy" and "timing" objects of the report.
nlohmann::json accuracy_json(const RunSummary& summary);
nlohmann::json timing_json(const motion::RunTiming& timing, double wall_s);

// Report for a run that could not start (load errors): status "error".
nlohmann::json load_error_report(const std::string& file, const interpreter::Diagnostic& first_error);
nlohmann::json run_report(const RunSummary& summary);

// The report's "status": completed, collision, error, interrupted (Ctrl-C), paused, halted.
const char* status_name(const interpreter::RunResult& r);
nlohmann::json trace_document(const std::string& program, const robots::Robot& robot,
                              const std::vector<motion::TraceSample>& samples);

// Writes `doc` to `path` through a temporary file and a rename, so a reader never sees half a
// file; the error when the file cannot be written.
Result<void> write_json_file(const std::string& path, const nlohmann::json& doc);

// The human-readable lines that follow "*Collision*" (dialect §10).
std::string collision_lines(const motion::CollisionReport& c);

}  // namespace asimov::app
