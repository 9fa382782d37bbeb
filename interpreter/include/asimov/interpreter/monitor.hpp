// The VAL monitor (dialect §9): the command table with unique-prefix matching, and the
// commands themselves over one Interpreter and its Simulator. app/cmd_monitor.cpp reads the
// lines (libedit or a pipe); everything the monitor prints goes to one stream, in order.
#pragma once
#include "asimov/interpreter/debugger.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/storage.hpp"
#include <atomic>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace asimov::interpreter {

// The commands: the rows of monitor_commands.def, in its (alphabetical) order.
enum class Command : int {
#define ASIMOV_COMMAND(id, name, usage, help) id,
#include "asimov/interpreter/monitor_commands.def"
  count
};

struct CommandInfo {
  std::string_view name;   // upper case, as HELP shows it
  std::string_view usage;  // arguments, for HELP
  std::string_view help;   // one line
};
const CommandInfo& command_info(Command c);

enum class Match { found, unknown, ambiguous };
struct CommandMatch {
  Match match = Match::unknown;
  Command command = Command::count;  // when found
};
// A command word in any case, or a unique prefix of one; an exact name wins (STORE, STOREL).
CommandMatch match_command(std::string_view word);

// WHERE (dialect §9): X Y Z O A T of `tool`, then the joints; %11.3f under 11-column labels.
std::string format_where(const motion::Location& tool, const robots::JointVector& joints);
// LISTL table of the location entries (others are skipped): transformations, then precision
// points, in the order given; name column at least 16 wide.
std::string format_location_table(const std::vector<GlobalEntry>& entries);

enum class CommandStatus { ok, failed, quit };
enum class ExecState { idle, completed, paused, halted, interrupted, error, collision };

class Monitor {
 public:
  Monitor(Interpreter& interp, motion::Simulator& sim, std::ostream& out);

  // One typed line: a command, or a line of a program being entered after `.PROGRAM`.
  CommandStatus execute(const std::string& line);
  bool entering_program() const { return !entry_.empty(); }
  int entry_step() const { return static_cast<int>(entry_.size()); }  // step of the next line typed
  // End of input: a program still being entered is loaded as typed (its missing .END is
  // then reported as LOAD would).
  CommandStatus end_of_input();

  // The outcome of the last program execution (EXECUTE, PROCEED, ...) and how many there were:
  // the Python Session's CommandError carries its program, line, kind and report.
  const std::optional<RunResult>& last_run() const { return last_run_; }
  std::uint64_t run_count() const { return run_count_; }
  // A run made outside the monitor (Python's Session.run): STATUS reports it as an EXECUTE's.
  void record_run(const RunResult& r, const std::string& main);

  // The program debugger behind DEBUG, SSTEP, XSTEP, BPT, NOBPT (and PROCEED's breakpoints).
  Debugger& debugger() { return debugger_; }

  // Asked before replacing a file or ZERO; unset (scripted mode): the answer is yes.
  std::function<bool(const std::string& question)> confirm;

  // Words that can complete `word`, the last word of `line` (whose text precedes the
  // cursor): commands first, then by context instructions, program or variable names.
  std::vector<std::string> completions(const std::string& line, const std::string& word) const;

 private:
  using Args = const std::string&;
  CommandStatus dispatch(Command c, Args rest);
  // A command error; `column` > 0 puts a caret under that column of the typed text.
  CommandStatus fail(std::string message, std::string detail = {}, int column = 0);
  CommandStatus report(const RunResult& r, const std::string& shown_name, bool execution);
  struct TemporaryRun {
    std::optional<Diagnostic> error;  // the load error, when the statement did not load
    RunResult result;                 // otherwise the run's outcome
  };
  TemporaryRun run_temporary(const char* name, const std::string& statement);
  CommandStatus run_instruction(const std::string& instruction);
  CommandStatus finish_entry();

  CommandStatus cmd_execute(Args rest, bool debug);
  CommandStatus cmd_bpt(Args rest, bool set);
  CommandStatus cmd_step(DebugMode mode);
  // A driven run's outcome: where the debugger stopped it, else as report() prints it.
  CommandStatus report_driven(const RunResult& r, const std::string& shown_name);
  CommandStatus cmd_do(Args rest);
  CommandStatus cmd_point(Args rest);
  CommandStatus cmd_list(Args rest, Command which);
  CommandStatus cmd_listp(Args rest);
  CommandStatus cmd_directory();
  CommandStatus cmd_load(Args rest);
  CommandStatus cmd_store(Args rest, bool locations_only);
  CommandStatus cmd_delete(Args rest);
  CommandStatus cmd_speed(Args rest);
  CommandStatus cmd_status();
  CommandStatus cmd_resume(bool retry);
  CommandStatus cmd_zero();
  CommandStatus cmd_help(Args rest);

  std::vector<std::string> sorted_programs() const;

  Interpreter& interp_;
  motion::Simulator& sim_;
  std::ostream& out_;
  std::string typed_;                 // the command line being executed, echoed in errors
  std::vector<std::string> entry_;    // lines of a program typed after .PROGRAM
  std::string last_program_;          // EXECUTE without a name runs this one
  ExecState state_ = ExecState::idle; // of the last EXECUTE
  int state_step_ = 0;                // where it stopped
  std::string state_program_;         // in which program (a CALLed one, when it differs)
  std::vector<TaskReport> tasks_;     // the tasks of the last execution, when it had several
  std::optional<motion::InterruptReport> halted_;  // the motion Ctrl-C halted in it
  std::optional<RunResult> last_run_;
  std::uint64_t run_count_ = 0;
  Debugger debugger_{interp_};
  void remember(const RunResult& r);
};

}  // namespace asimov::interpreter
