#include "app/serve/session.hpp"

#include "app/replay.hpp"
#include "app/report.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/motion/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <exception>

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

}  // namespace

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
}

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

json StudioSession::monitor(const Request& r) {
  std::string refusal;
  const std::optional<std::string> line = confine_monitor_line(r.line, refusal);
  interpreter::CommandStatus status = interpreter::CommandStatus::failed;
  if (!line) monitor_out_ << "*Illegal file name*  " << refusal << '\n';
  else status = monitor_->execute(*line);
  std::string text = monitor_out_.str();
  monitor_out_.str({});
  monitor_out_.clear();
  // The workspace's absolute path is the server's business, not the page's.
  const std::string root = workspace_.path().string() + "/";
  for (std::size_t at = 0; (at = text.find(root, at)) != std::string::npos;) text.erase(at, root.size());
  json answer = {{"type", "monitor"},
                 {"line", r.line},
                 {"output", text},
                 {"status", status == interpreter::CommandStatus::ok       ? "ok"
                            : status == interpreter::CommandStatus::quit ? "quit"
                                                                          : "failed"},
                 {"prompt", monitor_->entering_program() ? fmt::format("{}? ", monitor_->entry_step()) : "."}};
  // The arm where the monitor left it (EXECUTE, DO MOVE ...): the page poses its 3D view with
  // the moving bodies' world poses, in the replay data's `moving` order.
  const robots::JointVector& q = monitor_sim_->joints();
  answer["joints"] = std::vector<double>(q.data(), q.data() + monitor_sim_->robot().joint_count());
  const motion::Scene scene = motion::scene_bodies(monitor_sim_->cell(), false);
  std::vector<collision::Pose> frames, poses;
  motion::scene_poses(monitor_sim_->cell(), scene, q, frames, poses);
  json moving = json::array();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    if (!scene.bodies[i].is_static) {
      const Eigen::Quaterniond r(poses[i].rotation());
      const auto& t = poses[i].translation();
      moving.push_back({t.x(), t.y(), t.z(), r.x(), r.y(), r.z(), r.w()});
    }
  answer["poses"] = std::move(moving);
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
