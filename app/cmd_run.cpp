// `asimov run` and `asimov check`: load a .v2 file into the interpreter, check it, run it.
#include "app/atomic_file.hpp"
#include "asimov/collision/text_file.hpp"
#include "asimov/core/output_file.hpp"
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

// `path` "-" is standard output (`out`, after anything the program printed). False when the
// document could not be written (the message says which file and why).
bool write_report(const std::string& path, const nlohmann::json& doc, std::ostream& out, std::ostream& err) {
  if (path.empty()) return true;
  if (path == "-") {
    out << doc.dump(2) << '\n';
    out.flush();
    if (!out) err << "*Cannot write file*  standard output: the document was not written (a full disk or a closed pipe)\n";
    return static_cast<bool>(out);
  }
  const Result<void> written = write_json_file(path, doc);
  if (written) return true;
  err << "*Cannot write file*  " << written.error().message << '\n';
  return false;
}

// The run's own code stays (a collision is 3 even when its report was lost); a run that ended
// well and lost an output exits kExitOutputLost (docs/cli.md).
int with_outputs(int run_rc, bool outputs_written) {
  return outputs_written || run_rc != kExitCompleted ? run_rc : kExitOutputLost;
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
  const collision::InputFile f = collision::classify_input_file(path);
  if (f.missing) err << fmt::format("*File not found*  {}\n", path);
  else if (!f.not_regular.empty()) err << fmt::format("*Cannot read file*  {}: {}\n", path, f.not_regular);
  return !f.missing && f.not_regular.empty();
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
  // exist (it is never created), only a regular file is replaced, and no output may be an
  // input of the run or another output (docs/cli.md "Output files").
  for (const std::string* path : {&opt.report, &opt.trace, &opt.replay}) {
    if (path->empty() || (*path == "-" && path != &opt.replay)) continue;  // "-": stdout
    if (const auto ok = core::check_output_path(*path); !ok) {
      err << "*Cannot write file*  " << ok.error().message << '\n';
      return kExitUsage;
    }
  }
  if (const auto apart = core::check_outputs_apart({{"the program file", opt.file}, {"the cell file", opt.cell}},
                                                   {{"--report", opt.report}, {"--trace", opt.trace}, {"--replay", opt.replay}});
      !apart) {
    err << "*Cannot write file*  " << apart.error().message << '\n';
    return kExitUsage;
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
  // the main program and every program it calls can run; otherwise it stops here, exit 2 (a
  // report that could not be written is said, the code stays the program error's).
  const bool load_errors = print_diagnostics(diags, err);
  auto load_failed = [&] {
    write_report(opt.report, load_error_report(opt.file, *first_error(diags)), out, err);
    return kExitProgramError;
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
  // SIGTERM and SIGHUP stop it the same way (the report written), then end the process by that
  // signal once the outputs are written (docs/cli.md).
  sigint_flag().store(false);
  interp.limits().interrupt = &sigint_flag();
  install_sigint(true);
  install_termination();
  std::optional<RunProgress> progress;
  if (&err == &std::cerr && ::isatty(STDERR_FILENO) == 1) {
    progress.emplace(sim, opt.file, err);
    sim.set_pose_hook([&progress](double t, const robots::JointVector&) { progress->on_pose(t); });
  }
  interpreter::RunResult result = interp.run(main);
  sim.set_pose_hook({});
  progress.reset();  // erases the progress line before the messages
  // While the outputs are written a Ctrl-C is held (the writing is bounded: the recordings are
  // capped), so a second Ctrl-C never leaves a new report beside an old trace.
  install_sigint(false);
  out.flush();
  RunSummary summary = summarize_run(opt.file, std::move(result), sim, since(start));
  if (const auto* cell = interp.cell_state()) summary.workcell = workcell_json(*cell);

  for (const auto& w : summary.result.warnings) err << "Warning: " << interpreter::format_diagnostic(w);
  for (const auto& [name, truncated] : {std::pair{"trace", sim.recorders().trace.truncated},
                                        std::pair{"replay", sim.recorders().replay.truncated}})
    if (truncated)
      err << fmt::format("Warning: the {} holds its first {} samples only (docs/limits.md)\n", name,
                         motion::kMaxRecordedSamples);
  if (const auto* cell = interp.cell_state(); cell && cell->clock().events_dropped() > 0)
    err << fmt::format("Warning: the report's events hold the first {} only; {} later ones were counted, not kept "
                       "(docs/limits.md)\n", motion::kMaxEvents, cell->clock().events_dropped());
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
  // Every output is attempted even when one fails (a lost report does not take the trace with it).
  bool written = write_report(opt.report, run_report(summary), out, err);
  written = write_report(opt.trace, trace_document(summary.result.program, sim.robot(), sim.recorders().trace.samples), out, err) &&
            written;
  if (!opt.replay.empty())
    if (const auto page = write_file_atomically(opt.replay, replay_html(replay_assets, replay_data(opt.file, sim, summary.result)));
        !page) {
      err << "*Cannot write file*  " << page.error().message << '\n';
      written = false;
    }
  out.flush();
  if (!out && opt.report != "-" && opt.trace != "-") {  // TYPE output to a full disk or a closed pipe is not lost silently
    err << "*Cannot write file*  standard output: the program's output was not all written\n";
    written = false;
  }
  rc = with_outputs(rc, written);
  signal(SIGINT, SIG_DFL);
  reraise_termination();  // ends the process by SIGTERM / SIGHUP if one stopped the run
  return rc;
}

}  // namespace asimov::app
