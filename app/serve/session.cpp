#include "app/serve/session.hpp"

#include "app/replay.hpp"
#include "app/report.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/debugger.hpp"
#include "asimov/interpreter/storage.hpp"
#include "asimov/motion/location.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/motion/trajectory.hpp"
#include "asimov/motion/walk_observer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <exception>
#include <thread>

namespace asimov::serve {
namespace {

using nlohmann::json;

json error_json(const Request& r, const std::string& message, const std::string& detail) {
  return {{"type", "error"}, {"id", r.id}, {"request", kind_name(r.kind)}, {"message", message}, {"detail", detail}};
}

json diagnostics_json(const std::vector<interpreter::Diagnostic>& diags) {
  json out = json::array();
  for (const auto& d : diags)
    out.push_back({{"line", d.line},
                   {"column", d.column},
                   {"message", d.message},
                   {"detail", d.detail},
                   {"warning", d.warning},
                   {"program", d.program},
                   {"text", (d.warning ? "Warning: " : "") + interpreter::format_diagnostic(d)}});
  return out;
}

bool has_error(const std::vector<interpreter::Diagnostic>& diags) {
  return std::any_of(diags.begin(), diags.end(), [](const auto& d) { return !d.warning; });
}

// The editor's file name as the messages show it ("untitled.v2" when the page gives none).
std::string shown_name(const std::string& file) { return file.empty() ? "untitled.v2" : file; }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// The moving bodies' world poses at display joints q, in the replay data's `moving` order.
json moving_poses(const motion::Cell& cell, const motion::Scene& scene, const robots::JointVector& q) {
  std::vector<collision::Pose> frames, poses;
  motion::scene_poses(cell, scene, q, frames, poses);
  json moving = json::array();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    if (!scene.bodies[i].is_static) {
      const Eigen::Quaterniond r(poses[i].rotation());
      const auto& t = poses[i].translation();
      moving.push_back({t.x(), t.y(), t.z(), r.x(), r.y(), r.z(), r.w()});
    }
  return moving;
}

json joints_json(const robots::JointVector& q, int n) { return std::vector<double>(q.data(), q.data() + n); }

// A value as the monitor's lists show it.
std::string value_text(const interpreter::Value& v) {
  using interpreter::Kind;
  switch (interpreter::kind_of(v)) {
    case Kind::real: return interpreter::format_number(std::get<double>(v));
    case Kind::string: return "\"" + std::get<std::string>(v) + "\"";
    default: break;
  }
  if (const auto* loc = std::get_if<motion::Location>(&v)) {
    const motion::Xyzoat x = motion::decompose(*loc);
    return fmt::format("{:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f}", x[0], x[1], x[2], x[3], x[4], x[5]);
  }
  if (const auto* q = std::get_if<robots::JointVector>(&v)) {
    std::string out;
    for (Eigen::Index i = 0; i < q->size(); ++i) out += fmt::format("{}{:.3f}", i ? " " : "", (*q)[i]);
    return out;
  }
  return "?";
}

constexpr std::size_t kMaxVariablesShown = 500;  // a debug answer lists at most this many globals

}  // namespace

// The monitor arm's poses, streamed to the page as the walker simulates them (docs/studio.md
// "Stepping"). With a speed > 0 the poses are taken on the simulated clock every speed/60 s
// (so 60 a second of display at that speed) and sent when the simulated clock reaches them in
// wall time (the worker thread sleeps): the arm moves live, and a pause or abort (the interrupt
// flag) ends the wait at once. A pose is sent only after the checked pose at or after it was
// found free (the poses past a contact are dropped; the halting pose is sent). Speed 0: as fast
// as possible, only checked poses, at most one every 1/60 s of wall time, and the walk's last.
struct StudioSession::PoseStream final : motion::WalkObserver {
  using Clock = std::chrono::steady_clock;
  PoseStream(const motion::Simulator& sim, const std::atomic<bool>& interrupt)
      : sim(sim), scene(motion::scene_bodies(sim.cell(), false)), interrupt(interrupt) {}

  void begin(double s) {
    speed = s;
    anchored = false;
    pending.clear();
    sent = 0;
  }
  void on_walk_begin(const motion::Trajectory& tr) override {
    current = &tr;
    pending.clear();
    held.reset();
  }
  void on_stretch(const motion::Trajectory& tr, const motion::Stretch& s) override {
    if (!sink || !(speed > 0)) return;
    const double grid = speed / 60;
    for (double k = std::floor(s.t_from / grid) + 1; k * grid < s.t_to; ++k) {
      const double t = k * grid;
      const robots::JointVector q =
          s.blended                            ? motion::blended_joints_at(tr, t)
          : tr.kind == motion::PathKind::joint ? motion::joint_path_at(tr, t)
              : motion::line_path_between(sim.robot(), tr, s.sample_from, s.sample_to, t,
                                          pending.empty() ? (have_last ? &last_q : nullptr) : &pending.back().second)
                    .joints;
      pending.emplace_back(t, q);
    }
  }
  void on_checked_pose(double t, const robots::JointVector& q, bool contact) override {
    if (!sink) return;
    pending.emplace_back(t, q);
    if (!contact) release(false);
  }
  void on_contact(const motion::CollisionReport& report, const robots::JointVector& q_halt, double) override {
    if (!sink) return;
    while (!pending.empty() && pending.back().first > report.time_free_s) pending.pop_back();
    pending.emplace_back(report.time_free_s, q_halt);
    release(true);
  }
  void on_walk_end() override {
    if (!sink) return;
    // As fast as possible: the walk's last pose, when the throttle held it back.
    if (pending.empty() && held) pending.emplace_back(held->first, held->second);
    release(true);
  }

  // Sends the pending poses, paced on the wall clock; `last`: the walk's last one always goes.
  void release(bool last) {
    held.reset();
    for (std::size_t i = 0; i < pending.size(); ++i) {
      const auto& [t, q] = pending[i];
      const bool final_one = last && i + 1 == pending.size();
      const Clock::time_point now = Clock::now();
      if (speed > 0 && !interrupt.load(std::memory_order_relaxed)) {
        // The simulated clock against the wall clock, from the first pose of this request on; a
        // gap longer than 2 s of wall time (a long WAIT) or a lag behind re-anchors.
        Clock::time_point due = anchor_wall + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>((t - anchor_t) / speed));
        if (!anchored || due > now + std::chrono::seconds(2) || due + std::chrono::milliseconds(100) < now) {
          anchored = true;
          anchor_wall = now;
          anchor_t = t;
          due = now;
        }
        while (Clock::now() < due && !interrupt.load(std::memory_order_relaxed))
          std::this_thread::sleep_for(std::min<Clock::duration>(due - Clock::now(), std::chrono::milliseconds(5)));
      } else if (!final_one && sent > 0 && now - last_sent < std::chrono::microseconds(16667)) {
        held = pending[i];  // as fast as possible: at most one pose per display frame
        continue;
      }
      send(t, q);
    }
    if (!pending.empty()) {
      last_q = pending.back().second;
      have_last = true;
    }
    pending.clear();
  }
  void send(double t, const robots::JointVector& q) {
    json frame = {{"type", "frame"},
                  {"t", t},
                  {"step", current ? current->step : 0},
                  {"joints", joints_json(q, sim.robot().joint_count())},
                  {"poses", moving_poses(sim.cell(), scene, q)}};
    last_sent = Clock::now();
    ++sent;
    sink(frame.dump(-1, ' ', false, json::error_handler_t::replace));
  }

  const motion::Simulator& sim;
  const motion::Scene scene;
  const std::atomic<bool>& interrupt;
  std::function<void(std::string)> sink;
  double speed = 0;
  const motion::Trajectory* current = nullptr;
  std::vector<std::pair<double, robots::JointVector>> pending;
  robots::JointVector last_q;
  bool have_last = false;
  std::optional<std::pair<double, robots::JointVector>> held;  // a pose the throttle did not send
  bool anchored = false;
  Clock::time_point anchor_wall, last_sent;
  double anchor_t = 0;
  std::uint64_t sent = 0;
};

json check_json(const std::string& file, const std::string& text) {
  motion::Simulator sim(cell::default_cell());
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  return diagnostics_json(interp.load_source(text, shown_name(file)));
}

StudioSession::StudioSession(const StudioConfig& config, const Workspace& workspace)
    : config_(config), workspace_(workspace) {
  monitor_sim_ = std::make_unique<motion::Simulator>(config_.cell);
  monitor_interp_ = std::make_unique<interpreter::Interpreter>(*monitor_sim_, monitor_out_);
  monitor_interp_->set_input(no_input_, false);
  monitor_interp_->limits().interrupt = &interrupt_;
  monitor_interp_->limits().files_root = workspace_.path().string();
  monitor_ = std::make_unique<interpreter::Monitor>(*monitor_interp_, *monitor_sim_, monitor_out_);
  stream_ = std::make_unique<PoseStream>(*monitor_sim_, interrupt_);
  monitor_sim_->add_observer(*stream_);
}

void StudioSession::set_frame_sink(std::function<void(std::string)> sink) { stream_->sink = std::move(sink); }

StudioSession::~StudioSession() = default;

json StudioSession::hello() const {
  return {{"type", "hello"},
          {"cell", config_.cell_name},
          {"robot", config_.cell.robot.name},
          {"workspace", workspace_.path().filename().string()},
          {"file", config_.first_file},
          {"text", config_.first_text},
          {"replay", config_.replay_assets_error.empty()},
          {"limits", {{"message_bytes", kMaxMessageBytes}, {"text_bytes", kMaxTextBytes}, {"line_bytes", kMaxLineBytes}}}};
}

json StudioSession::handle(const Request& r) {
  interrupt_.store(false);
  pausing_.store(false);
  try {
    json answer;
    switch (r.kind) {
      case RequestKind::check:
        answer = {{"type", "check"}, {"file", shown_name(r.file)}, {"diagnostics", check_json(r.file, r.text)}};
        break;
      case RequestKind::monitor: answer = monitor(r); break;
      case RequestKind::run: answer = run(r); break;
      case RequestKind::abort: answer = {{"type", "abort"}}; break;  // the server set the flag already
      case RequestKind::list: answer = {{"type", "list"}, {"files", workspace_.list()}}; break;
      case RequestKind::open: answer = open(r); break;
      case RequestKind::save: answer = save(r); break;
      case RequestKind::replay: answer = replay(r); break;
      case RequestKind::scene: answer = scene(); break;
      case RequestKind::debug: answer = debug(r); break;
      case RequestKind::pause: answer = {{"type", "pause"}}; break;  // the server set the flags already
    }
    if (answer.value("type", "") != "error") answer["id"] = r.id;
    return answer;
  } catch (const std::exception& e) {  // a bug of ours must not end the server: the page is told
    return error_json(r, "*Internal error*", e.what());
  }
}

std::optional<std::string> StudioSession::confine_monitor_line(const std::string& line, std::string& refusal) const {
  std::size_t at = 0;
  while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
  std::size_t end = at;
  while (end < line.size() && std::isalpha(static_cast<unsigned char>(line[end]))) ++end;
  if (monitor_->entering_program() || end == at) return line;
  const interpreter::CommandMatch m = interpreter::match_command(line.substr(at, end - at));
  using interpreter::Command;
  if (m.match != interpreter::Match::found ||
      (m.command != Command::load && m.command != Command::store && m.command != Command::storel))
    return line;
  std::size_t name_at = end;
  while (name_at < line.size() && std::isspace(static_cast<unsigned char>(line[name_at]))) ++name_at;
  std::size_t name_end = name_at;
  while (name_end < line.size() && line[name_end] != ',' && !std::isspace(static_cast<unsigned char>(line[name_end]))) ++name_end;
  std::string name = line.substr(name_at, name_end - name_at);
  if (name.empty()) return line;  // the monitor says what is missing
  if (std::filesystem::path(name).extension().empty()) name += ".v2";
  // The name must stay beneath the workspace: LOAD reads an existing file there, STORE writes
  // one there (its folder must resolve beneath). The monitor then gets the full path.
  const bool load = m.command == Command::load;
  if (name.front() == '/' || name.find('\\') != std::string::npos ||
      std::filesystem::path(name).lexically_normal().string().rfind("..", 0) == 0) {
    refusal = fmt::format("{}: outside the workspace", name);
    return std::nullopt;
  }
  if (load && !workspace_.is_file(name)) {
    if (auto r = workspace_.read(name); !r) refusal = r.error().detail;
    else refusal = fmt::format("{}: not a file of the workspace", name);
    return std::nullopt;
  }
  if (!load) {
    const auto parent = std::filesystem::path(name).parent_path();
    if (!parent.empty()) {
      refusal = fmt::format("{}: the studio stores only into the workspace folder itself", name);
      return std::nullopt;
    }
  }
  return line.substr(0, name_at) + (workspace_.path() / name).string() + line.substr(name_end);
}

std::string StudioSession::take_monitor_output() {
  std::string text = monitor_out_.str();
  monitor_out_.str({});
  monitor_out_.clear();
  // The workspace's absolute path is the server's business, not the page's.
  const std::string root = workspace_.path().string() + "/";
  for (std::size_t at = 0; (at = text.find(root, at)) != std::string::npos;) text.erase(at, root.size());
  return text;
}

void StudioSession::add_arm(json& answer) const {
  // The arm where the monitor left it (EXECUTE, DO MOVE ...): the page poses its 3D view with
  // the moving bodies' world poses, in the replay data's `moving` order.
  const robots::JointVector& q = monitor_sim_->joints();
  answer["joints"] = joints_json(q, monitor_sim_->robot().joint_count());
  answer["poses"] = moving_poses(monitor_sim_->cell(), stream_->scene, q);
}

json StudioSession::monitor(const Request& r) {
  std::string refusal;
  const std::optional<std::string> line = confine_monitor_line(r.line, refusal);
  interpreter::CommandStatus status = interpreter::CommandStatus::failed;
  stream_->begin(0);  // the console's commands: the arm's poses as fast as they are simulated
  if (!line) monitor_out_ << "*Illegal file name*  " << refusal << '\n';
  else status = monitor_->execute(*line);
  json answer = {{"type", "monitor"},
                 {"line", r.line},
                 {"output", take_monitor_output()},
                 {"status", status == interpreter::CommandStatus::ok       ? "ok"
                            : status == interpreter::CommandStatus::quit ? "quit"
                                                                          : "failed"},
                 {"prompt", monitor_->entering_program() ? fmt::format("{}? ", monitor_->entry_step()) : "."}};
  add_arm(answer);
  return answer;
}

json StudioSession::run(const Request& r) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const std::string file = shown_name(r.file);
  motion::Simulator sim(config_.cell);
  sim.recorders().replay.grid_s = app::kReplayGridS;
  std::ostringstream out, messages;
  std::istringstream no_input;
  interpreter::Interpreter interp(sim, out);
  interp.set_input(no_input, false);
  interp.limits().interrupt = &interrupt_;
  interp.limits().files_root = workspace_.path().string();
  const auto diags = interp.load_source(r.text, file);
  json answer = {{"type", "run"}, {"file", file}, {"diagnostics", diagnostics_json(diags)}};
  for (const auto& d : diags) messages << (d.warning ? "Warning: " : "") << interpreter::format_diagnostic(d);
  if (has_error(diags)) {
    answer["status"] = "error";
    answer["messages"] = messages.str();
    return answer;
  }
  std::string main = lower(r.main);
  if (main.empty()) {
    const auto names = interp.program_names();
    if (names.empty()) return error_json(r, "*Undefined program or variable name*", file + " holds no program");
    main = names.front();
  }
  if (!interp.has_program(main)) return error_json(r, "*Undefined program or variable name*", main);
  interpreter::RunResult result = interp.run(main);
  app::RunSummary summary =
      app::summarize_run(file, std::move(result), sim, std::chrono::duration<double>(Clock::now() - start).count());
  if (const auto* cell = interp.cell_state()) summary.workcell = app::workcell_json(*cell);
  for (const auto& w : summary.result.warnings) messages << "Warning: " << interpreter::format_diagnostic(w);
  using interpreter::RunStatus;
  switch (summary.result.status) {
    case RunStatus::completed: messages << fmt::format("Program completed: {}\n", main) << summary.closest; break;
    case RunStatus::error:
    case RunStatus::interrupted:
      messages << interpreter::format_diagnostic(summary.result.error) << interpreter::format_interrupt(summary.result);
      break;
    case RunStatus::paused:
    case RunStatus::halted: messages << interpreter::format_pause(summary.result) << '\n'; break;
    case RunStatus::collision:
      messages << interpreter::format_diagnostic(summary.result.error) << app::collision_lines(summary.result.collision);
      break;
  }
  json data = app::replay_data(file, sim, summary.result, r.text);
  answer["status"] = app::status_name(summary.result);
  answer["output"] = out.str();
  answer["messages"] = messages.str();
  answer["report"] = app::run_report(summary);
  answer["line"] = summary.result.line;
  answer["program"] = summary.result.program;
  answer["replay"] = data;
  last_replay_ = std::move(data);
  last_file_ = file;
  return answer;
}

// --- the program debugger (docs/studio.md "Stepping") ------------------------------------------

json StudioSession::debug(const Request& r) {
  using interpreter::Debugger;
  const std::string file = shown_name(r.file);
  Debugger& dbg = monitor_->debugger();
  json answer = {{"type", "debug"}, {"action", r.action == DebugAction::start ? "start" : r.action == DebugAction::step ? "step"
                                               : r.action == DebugAction::into ? "into" : r.action == DebugAction::go ? "go"
                                               : r.action == DebugAction::abort ? "abort" : "state"}};
  const bool stopped = monitor_interp_->can_resume();
  // Nothing stopped: step, into and go start the editor's program (stopped before its first
  // step, or run to a breakpoint); start always starts it afresh.
  const bool starting = r.action == DebugAction::start ||
      (!stopped && (r.action == DebugAction::step || r.action == DebugAction::into || r.action == DebugAction::go));
  stream_->begin(r.speed);
  if (starting) {
    if (r.text.empty()) return error_json(r, "*No program to resume*", "no program text to start");
    if (stopped) monitor_->execute("ABORT");
    // The program to start: the first of the text, unless one is named.
    std::string main = lower(r.main);
    if (main.empty()) {
      motion::Simulator scratch(cell::default_cell());
      std::ostringstream ignored;
      interpreter::Interpreter first(scratch, ignored);
      first.load_source(r.text, file);
      const auto names = first.program_names();
      if (names.empty()) return error_json(r, "*Undefined program or variable name*", file + " holds no program");
      main = names.front();
    }
    const auto diags = monitor_interp_->load_source(r.text, file);
    take_monitor_output();
    answer["diagnostics"] = diagnostics_json(diags);
    if (has_error(diags)) {
      std::string messages;
      for (const auto& d : diags) messages += (d.warning ? "Warning: " : "") + interpreter::format_diagnostic(d);
      answer["status"] = "error";
      answer["output"] = messages;
      add_debug_state(answer);
      return answer;
    }
    if (!monitor_interp_->has_program(main)) return error_json(r, "*Undefined program or variable name*", main);
    debug_file_ = file;
    debug_main_ = main;
  }
  // The page's breakpoints, by the lines of its editor: those it set before are cleared first
  // (the console's BPT ones stay).
  for (const auto& b : page_breakpoints_) dbg.clear_breakpoint(b);
  page_breakpoints_.clear();
  breakpoint_lines_.clear();
  json refused = json::array();
  for (int line : r.breakpoints) {
    if (const auto b = interpreter::step_at_line(*monitor_interp_, debug_file_.empty() ? file : debug_file_, line)) {
      dbg.set_breakpoint(*b);
      page_breakpoints_.insert(*b);
      breakpoint_lines_.push_back(line);
    } else {
      refused.push_back(line);
    }
  }
  answer["refused"] = std::move(refused);
  std::string command;
  switch (r.action) {
    case DebugAction::start: command = "DEBUG " + debug_main_; break;
    case DebugAction::step: command = starting ? "DEBUG " + debug_main_ : "SSTEP"; break;
    case DebugAction::into: command = starting ? "DEBUG " + debug_main_ : "XSTEP"; break;
    case DebugAction::go: command = starting ? "EXECUTE " + debug_main_ : "PROCEED"; break;
    case DebugAction::abort: command = stopped ? "ABORT" : ""; break;
    case DebugAction::state: break;
  }
  const std::uint64_t runs = monitor_->run_count();
  if (!command.empty()) {
    const auto status = monitor_->execute(command);
    answer["command"] = command;
    answer["ok"] = status == interpreter::CommandStatus::ok;
  }
  answer["output"] = take_monitor_output();
  // How the command ended: a stop of the debugger's (step, breakpoint), the pause button, or
  // the run's own end (completed, error, collision, PAUSE in the program ...).
  const auto& last = monitor_->last_run();
  const bool ran = monitor_->run_count() != runs && last;
  std::string stop = "none";
  if (ran) {
    if (dbg.last_stop() == interpreter::DebugStop::breakpoint) stop = "breakpoint";
    else if (dbg.last_stop() == interpreter::DebugStop::step) stop = "step";
    else if (pausing_.load() && last->status == interpreter::RunStatus::interrupted) stop = "pause";
    else stop = app::status_name(*last);
  } else if (r.action == DebugAction::abort && stopped) {
    stop = "aborted";
  }
  answer["stop"] = stop;
  if (ran && last->status == interpreter::RunStatus::collision) {
    answer["report"] = answer["output"];
    answer["line"] = last->line;
  }
  add_debug_state(answer);
  return answer;
}

void StudioSession::add_debug_state(json& answer) const {
  const interpreter::Debugger& dbg = monitor_->debugger();
  const bool stopped = monitor_interp_->can_resume();
  answer["stopped"] = stopped;
  answer["file"] = debug_file_;
  answer["main"] = debug_main_;
  answer["breakpoints"] = breakpoint_lines_;
  // Where the stopped program goes on: the debugger's place, else where the run stopped.
  json place = nullptr;
  const auto& last = monitor_->last_run();
  if (stopped && dbg.last_stop() != interpreter::DebugStop::none) {
    const auto& p = dbg.place();
    place = {{"program", p.program}, {"step", p.step}, {"line", p.line}, {"file", p.file}, {"text", p.text}, {"depth", p.depth}};
  } else if (stopped && last && last->line > 0) {
    place = {{"program", last->program}, {"step", last->step}, {"line", last->line}, {"file", last->error.file},
             {"text", ""}, {"depth", 0}};
  }
  answer["place"] = std::move(place);
  // The variables the stopped program reads: the globals (V+ programs use globals unless they
  // declare AUTO or LOCAL; a CALLed program's parameters are its caller's variables).
  json vars = json::array();
  const auto entries = interpreter::global_entries(monitor_interp_->memory());
  for (std::size_t i = 0; i < entries.size() && i < kMaxVariablesShown; ++i) {
    const auto& e = entries[i];
    vars.push_back({{"name", e.name}, {"kind", interpreter::kind_name(interpreter::kind_of(*e.value))}, {"value", value_text(*e.value)}});
  }
  answer["variables"] = std::move(vars);
  answer["variables_omitted"] = entries.size() > kMaxVariablesShown ? entries.size() - kMaxVariablesShown : 0;
  // The tasks: those of a run that EXECUTEd others, else the one the debugger drives.
  json tasks = json::array();
  if (last && !last->tasks.empty()) {
    for (const auto& t : last->tasks) tasks.push_back({{"number", t.number}, {"program", t.program}, {"state", t.state}});
  } else if (last && !debug_main_.empty()) {
    std::string state = stopped ? fmt::format("stopped at {}, step {}", last->program, last->step) : app::status_name(*last);
    tasks.push_back({{"number", 0}, {"program", debug_main_}, {"state", state}});
  }
  answer["tasks"] = std::move(tasks);
  add_arm(answer);
}

json StudioSession::open(const Request& r) {
  Result<std::string> text = workspace_.read(r.file);
  if (!text) return error_json(r, text.error().message, text.error().detail);
  return {{"type", "open"}, {"file", r.file}, {"text", std::move(*text)}};
}

json StudioSession::save(const Request& r) {
  if (auto w = workspace_.write(r.file, r.text); !w) return error_json(r, w.error().message, w.error().detail);
  return {{"type", "save"}, {"file", r.file}, {"bytes", r.text.size()}};
}

json StudioSession::replay(const Request& r) {
  if (!last_replay_) return error_json(r, "*Nothing to replay*", "run a program first");
  if (!config_.replay_assets_error.empty()) return error_json(r, "*Cannot write replay*", config_.replay_assets_error);
  Result<app::ReplayAssets> assets = app::load_replay_assets();
  if (!assets) return error_json(r, "*Cannot write replay*", assets.error().message);
  if (std::filesystem::path(r.file).extension() != ".html")
    return error_json(r, "*Illegal file name*", r.file + ": a replay page is an .html file");
  if (auto w = workspace_.write(r.file, app::replay_html(*assets, *last_replay_)); !w)
    return error_json(r, w.error().message, w.error().detail);
  return {{"type", "replay"}, {"file", r.file}, {"of", last_file_}};
}

json StudioSession::scene() {
  // The cell at rest: the replay data of a run that did nothing (bodies, one frame).
  motion::Simulator sim(config_.cell);
  sim.recorders().replay.grid_s = app::kReplayGridS;
  interpreter::RunResult nothing;
  return {{"type", "scene"}, {"replay", app::replay_data("", sim, nothing)}};
}

}  // namespace asimov::serve
