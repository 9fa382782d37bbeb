// `asimov run` and `asimov check`: load a .v2 file into the interpreter, check it, run it.
#include "app/atomic_file.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/replay.hpp"
#include "app/report.hpp"
#include "app/sigint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <optional>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <ostream>

#include <unistd.h>

namespace asimov::app {
namespace {

// Prints every diagnostic; returns true when one of them is an error (not a warning).
bool print_diagnostics(const std::vector<interpreter::Diagnostic>& diags, std::ostream& err) {
  bool any_error = false;
  for (const auto& d : diags) {
    err << (d.warning ? "Warning: " : "") << interpreter::format_diagnostic(d);
    any_error = any_error || !d.warning;
  }
  return any_error;
}

const interpreter::Diagnostic* first_error(const std::vector<interpreter::Diagnostic>& diags) {
  for (const auto& d : diags)
    if (!d.warning) return &d;
  return nullptr;
}

// `path` "-" is standard output (`out`, after anything the program printed).
int write_report(const std::string& path, const nlohmann::json& doc, std::ostream& out, std::ostream& err) {
  if (path.empty()) return kExitCompleted;
  if (path == "-") {
    out << doc.dump(2) << '\n';
    out.flush();
    return out ? kExitCompleted : kExitUsage;
  }
  const Result<void> written = write_json_file(path, doc);
  if (written) return kExitCompleted;
  err << "*Cannot write file*  " << written.error().message << '\n';
  return kExitUsage;
}

// Progress of a long run on a terminal (stderr): simulated time, the program line of the motion
// being carried out and the poses checked, redrawn in place at most every 0.25 s once the run has
// taken 0.5 s (ASIMOV_PROGRESS_DELAY_S overrides the delay, for tests), erased when it ends. Fed
// by the simulator's pose hook, on the run's own thread; off when stderr is not a terminal.
class RunProgress {
 public:
  RunProgress(const motion::Simulator& sim, std::string file, std::ostream& err)
      : sim_(sim), file_(std::move(file)), err_(err) {
    const char* delay = std::getenv("ASIMOV_PROGRESS_DELAY_S");
    next_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(delay && *delay ? std::atof(delay) : 0.5));
  }
  void on_pose(double time_s) {
    if (++poses_ % 64 != 0 || Clock::now() < next_) return;
    next_ = Clock::now() + std::chrono::milliseconds(250);
    // The step is all the simulator knows mid-run; program and line come with the run's result.
    if (const int step = sim_.motion_step(); step != step_) step_ = step, where_ = fmt::format("step {}", step);
    err_ << fmt::format("\r\033[K  t = {:.3f} s  {}  {} poses checked", time_s, where_, sim_.recorders().counts.poses) << std::flush;
    drawn_ = true;
  }
  ~RunProgress() {
    if (drawn_) err_ << "\r\033[K" << std::flush;
  }

 private:
  using Clock = std::chrono::steady_clock;
  const motion::Simulator& sim_;
  std::string file_;
  std::ostream& err_;
  Clock::time_point next_;
  std::uint64_t poses_ = 0;
  int step_ = -1;
  std::string where_;
  bool drawn_ = false;
};

}  // namespace

bool require_file(const std::string& path, std::ostream& err) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    err << fmt::format("*File not found*  {}\n", path);
    return false;
  }
  return true;
}

int check_command(const std::string& file, std::ostream& out, std::ostream& err) {
  if (!require_file(file, err)) return kExitUsage;
  motion::Simulator sim(cell::default_cell());
  interpreter::Interpreter interp(sim, out);
  const auto diags = interp.load_file(file);
  if (print_diagnostics(diags, err)) return kExitProgramError;
  err << fmt::format("{}: {} program(s), no errors\n", file, interp.program_names().size());
  return kExitCompleted;
}

int run_command(const RunOptions& opt, std::ostream& out, std::ostream& err) {
  if (!require_file(opt.file, err)) return kExitUsage;
  if (opt.report == "-" && opt.trace == "-") {  // two documents on one stream parse as neither
    err << "*Invalid argument*  --report - and --trace - cannot both write to stdout\n";
    return kExitUsage;
  }
  // Output files are checked before anything runs (exit 1 means nothing ran): the folder must
  // exist (it is never created) and the name must not be a folder.
  for (const std::string* path : {&opt.report, &opt.trace, &opt.replay}) {
    if (path->empty() || (*path == "-" && path != &opt.replay)) continue;  // "-": stdout
    std::error_code ec;
    const auto folder = std::filesystem::path(*path).parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder, ec)) {
      err << fmt::format("*Cannot write file*  {}: no folder {}\n", *path, folder.string());
      return kExitUsage;
    }
    if (std::filesystem::is_directory(*path, ec)) {
      err << fmt::format("*Cannot write file*  {}: is a folder\n", *path);
      return kExitUsage;
    }
  }
  // Files are confined to one folder: --files DIR, or the program file's own (dialect §7a).
  if (std::error_code ec; !opt.files.empty() && !std::filesystem::is_directory(opt.files, ec)) {
    err << fmt::format("*File not found*  --files {}: not a folder\n", opt.files);
    return kExitUsage;
  }
  ReplayAssets replay_assets;  // read before the run: a missing viewer is a usage error, not a late surprise
  if (!opt.replay.empty()) {
    Result<ReplayAssets> assets = load_replay_assets();
    if (!assets) {
      err << "*Cannot write replay*  " << assets.error().message << '\n';
      return kExitUsage;
    }
    replay_assets = std::move(assets).value();
  }
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const Clock::time_point start = Clock::now();
  auto cell = cell::load_cell_for_command(opt.cell, err);
  if (!cell) return kExitUsage;
  const double cell_s = since(start);
  motion::Simulator sim(std::move(*cell));
  sim.recorders().timing.timing.preprocess_s += cell_s;
  sim.recorders().trace.on = !opt.trace.empty();
  if (!opt.replay.empty()) sim.recorders().replay.grid_s = kReplayGridS;
  interpreter::Interpreter interp(sim, out);
  interp.set_input(std::cin, ::isatty(STDIN_FILENO) == 1);  // PROMPT asks again only at a terminal
  const std::filesystem::path file_folder = std::filesystem::path(opt.file).parent_path();
  interp.limits().files_root = !opt.files.empty() ? opt.files : file_folder.empty() ? "." : file_folder.string();
  const Clock::time_point parse_start = Clock::now();
  const auto diags = interp.load_file(opt.file);
  sim.recorders().timing.timing.parse_s += since(parse_start);
  // A program with an error is loaded marked not executable (dialect §8): the run goes on when
  // the main program and every program it calls can run; otherwise it stops here, exit 2.
  const bool load_errors = print_diagnostics(diags, err);
  auto load_failed = [&] {
    const int rc = write_report(opt.report, load_error_report(opt.file, *first_error(diags)), out, err);
    return rc != kExitCompleted ? rc : kExitProgramError;
  };
  if (load_errors && interp.program_names().empty()) return load_failed();

  std::string main = opt.main;
  if (main.empty()) {
    const auto names = interp.program_names();
    if (names.empty()) {
      err << fmt::format("*Undefined program or variable name*  {} holds no program\n", opt.file);
      return kExitUsage;
    }
    main = names.front();
  }
  // Names are case-insensitive and stored in lower case (dialect §1).
  std::transform(main.begin(), main.end(), main.begin(), [](unsigned char c) { return std::tolower(c); });
  if (!interp.has_program(main)) {
    if (load_errors) return load_failed();
    err << fmt::format("*Undefined program or variable name*  {}\n", main);
    return kExitUsage;
  }
  if (const auto blocked = interp.not_executable_from(main)) {  // main's own errors say why
    if (*blocked != main) err << fmt::format("*Program not executable*  {} (reached from {})\n", *blocked, main);
    return load_failed();
  }

  // Ctrl-C stops the program where it is (the arm at its last checked pose) and the report and
  // trace are still written; a second Ctrl-C ends the process at once.
  sigint_flag().store(false);
  interp.limits().interrupt = &sigint_flag();
  install_sigint(true);
  std::optional<RunProgress> progress;
  if (&err == &std::cerr && ::isatty(STDERR_FILENO) == 1) {
    progress.emplace(sim, opt.file, err);
    sim.set_pose_hook([&progress](double t, const robots::JointVector&) { progress->on_pose(t); });
  }
  interpreter::RunResult result = interp.run(main);
  sim.set_pose_hook({});
  progress.reset();  // erases the progress line before the messages
  signal(SIGINT, SIG_DFL);
  out.flush();
  RunSummary summary = summarize_run(opt.file, std::move(result), sim, since(start));
  if (const auto* cell = interp.cell_state()) summary.workcell = workcell_json(*cell);

  for (const auto& w : summary.result.warnings) err << "Warning: " << interpreter::format_diagnostic(w);
  int rc = kExitCompleted;
  switch (summary.result.status) {
    case interpreter::RunStatus::completed:
      err << fmt::format("Program completed: {}\n", main) << summary.closest;
      break;
    case interpreter::RunStatus::error:
    case interpreter::RunStatus::interrupted:
      err << interpreter::format_diagnostic(summary.result.error) << interpreter::format_interrupt(summary.result);
      rc = summary.result.status == interpreter::RunStatus::interrupted ? kExitInterrupted : kExitProgramError;
      break;
    case interpreter::RunStatus::paused:  // PAUSE / HALT end a batch run: nobody can PROCEED here
    case interpreter::RunStatus::halted:
      err << interpreter::format_pause(summary.result) << '\n';
      break;
    case interpreter::RunStatus::collision:
      err << interpreter::format_diagnostic(summary.result.error) << collision_lines(summary.result.collision);
      rc = kExitCollision;
      break;
  }
  if (int w = write_report(opt.report, run_report(summary), out, err); w != kExitCompleted) return w;
  if (int w = write_report(opt.trace, trace_document(summary.result.program, sim.robot(), sim.recorders().trace.samples), out, err);
      w != kExitCompleted)
    return w;
  if (!opt.replay.empty())
    if (const auto written = write_file_atomically(opt.replay, replay_html(replay_assets, replay_data(opt.file, sim, summary.result)));
        !written) {
      err << "*Cannot write file*  " << written.error().message << '\n';
      return kExitUsage;
    }
  return rc;
}

}  // namespace asimov::app
