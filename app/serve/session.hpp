// One studio session (one browser tab's WebSocket): what the page asks, answered. No networking
// here: server.cpp hands each parsed Request to handle() on the session's own worker thread and
// sends the JSON back, so this class is tested directly (tests/app/test_serve.cpp).
#pragma once
#include "app/serve/protocol.hpp"
#include "app/serve/workspace.hpp"

#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/monitor.hpp"
#include "asimov/motion/simulator.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <vector>
#include <sstream>
#include <string>

namespace asimov::serve {

// What every session of one server shares (read-only once the server runs).
struct StudioConfig {
  motion::Cell cell;              // every run and the monitor use a copy
  std::string cell_name;          // "built-in default cell" or the cell file
  std::string first_file;         // the program the editor opens with
  std::string first_text;
  std::string replay_assets_error;  // non-empty: replay pages cannot be written (why)
};

class StudioSession {
 public:
  StudioSession(const StudioConfig& config, const Workspace& workspace);
  ~StudioSession();

  // The answer to one request: {"type": kind, "id": id, ...} or {"type": "error", "id",
  // "message", "detail"}. Never throws.
  nlohmann::json handle(const Request& request);
  // The hello the page gets first: the cell, the workspace's name, the first program.
  nlohmann::json hello() const;
  // Stops the run or monitor command under way at its next step or checked pose (any thread).
  void abort() { interrupt_.store(true); }
  // Pauses the program the debugger runs (a `debug` go or step under way) at its next step or
  // checked pose, resumable (any thread). Nothing when nothing runs.
  void pause() {
    pausing_.store(true);
    interrupt_.store(true);
  }
  // Where the arm's poses go while the session's monitor arm moves (frames, docs/studio.md
  // "Stepping"): called on the thread running handle(), a JSON text each. Unset: none sent.
  void set_frame_sink(std::function<void(std::string)> sink);

 private:
  nlohmann::json check(const Request& r);
  nlohmann::json monitor(const Request& r);
  nlohmann::json run(const Request& r);
  nlohmann::json open(const Request& r);
  nlohmann::json save(const Request& r);
  nlohmann::json replay(const Request& r);
  nlohmann::json scene();
  nlohmann::json debug(const Request& r);
  // The monitor's output since the last call, the workspace's absolute path taken out.
  std::string take_monitor_output();
  // The arm's joints and the moving bodies' world poses where the monitor's arm stands.
  void add_arm(nlohmann::json& answer) const;
  // The stopped program's place, variables and tasks, the breakpoints (debug answers).
  void add_debug_state(nlohmann::json& answer) const;
  // LOAD / STORE / STOREL name files: the name is resolved in the workspace (never outside).
  std::optional<std::string> confine_monitor_line(const std::string& line, std::string& refusal) const;

  const StudioConfig& config_;
  const Workspace& workspace_;
  std::atomic<bool> interrupt_{false};
  std::atomic<bool> pausing_{false};
  // The monitor arm's poses streamed to the page as it moves (session.cpp); declared before the
  // simulator it watches, so it outlives it.
  struct PoseStream;
  std::unique_ptr<PoseStream> stream_;
  // The program debugger's state for the page: the breakpoints the page set (by program and
  // step), the file and program it started.
  std::set<interpreter::Breakpoint> page_breakpoints_;
  std::vector<int> breakpoint_lines_;
  std::string debug_file_, debug_main_;
  // The monitor console's own arm and memory, kept between commands (as a terminal monitor's).
  std::unique_ptr<motion::Simulator> monitor_sim_;
  std::ostringstream monitor_out_;
  std::istringstream no_input_;  // PROMPT in the studio: no terminal, an *Illegal value*
  std::unique_ptr<interpreter::Interpreter> monitor_interp_;
  std::unique_ptr<interpreter::Monitor> monitor_;
  std::optional<nlohmann::json> last_replay_;  // the last run's replay data (replay export)
  std::string last_file_;
};

// The diagnostics of `text` as `file` (check's, nothing runs) as JSON: line, column, message,
// detail, warning, text (formatted as `asimov check` prints it).
nlohmann::json check_json(const std::string& file, const std::string& text);

}  // namespace asimov::serve
