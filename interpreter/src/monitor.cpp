#include "asimov/interpreter/monitor.hpp"
#include "vplus_words.hpp"

#include "asimov/collision/text_file.hpp"

#include "evaluator.hpp"
#include "limits.hpp"
#include "monitor_text.hpp"
#include "parser.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>

namespace asimov::interpreter {
namespace {

using namespace monitor_text;

// The VAL text of a message kind (errors.cpp holds the texts).
std::string val(Message kind) { return std::string(message_text(kind)); }

constexpr std::array<CommandInfo, static_cast<std::size_t>(Command::count)> kCommands = {{
#define ASIMOV_COMMAND(id, name, usage, help) {name, usage, help},
#include "asimov/interpreter/monitor_commands.def"
}};
constexpr bool alphabetical() {
  for (std::size_t i = 1; i < kCommands.size(); ++i)
    if (!(kCommands[i - 1].name < kCommands[i].name)) return false;
  return true;
}
static_assert(alphabetical(), "monitor_commands.def: the rows in alphabetical order");

constexpr const char* kDoProgram = "do.tmp";      // DO runs as this one-statement program
constexpr const char* kExecProgram = "exec.tmp";  // EXECUTE prog(args) calls prog from this one
constexpr const char* kTypedFile = "monitor";     // file name of programs typed at the prompt

// -0.000 prints as 0.000 (dialect §9).
double shown3(double x) { return std::round(x * 1000.0) == 0 ? 0.0 : x; }

std::string labels(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += fmt::format("{:>11}", n);
  return s;
}

std::string numbers(const double* v, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += fmt::format("{:11.3f}", shown3(v[i]));
  return s;
}

std::vector<std::string> joint_labels(std::size_t n) {
  std::vector<std::string> v;
  for (std::size_t i = 1; i <= n; ++i) v.push_back(fmt::format("J{}", i));
  return v;
}

const std::vector<std::string> kXyzoat = {"X", "Y", "Z", "O", "A", "T"};

// A name as LISTL, DELETE and POINT take it: `x`, `$s`, `#p`, `a[]`, `a[1,2]`.
struct NameSpec {
  std::string base;         // normalized, with prefix
  bool whole_array = false; // a[]
  bool element = false;     // a[i,...]
  Index index{0, 0, 0};
  bool valid = false;
};

NameSpec parse_name(const std::string& text) {
  NameSpec spec;
  const std::string t = trim(text);
  const auto open = t.find('[');
  const std::string base = trim(t.substr(0, open));
  if (base.empty()) return spec;
  const std::size_t first = (base[0] == '$' || base[0] == '#') ? 1 : 0;
  if (first >= base.size() || !std::isalpha(static_cast<unsigned char>(base[first]))) return spec;
  for (std::size_t i = first; i < base.size(); ++i)
    if (!std::isalnum(static_cast<unsigned char>(base[i])) && base[i] != '.' && base[i] != '_') return spec;
  spec.base = normalize_name(base);
  if (open != std::string::npos) {
    if (t.back() != ']') return spec;
    const std::string inside = trim(t.substr(open + 1, t.size() - open - 2));
    if (inside.empty()) {
      spec.whole_array = true;
    } else {
      const auto parts = split_list(inside);
      if (parts.size() > 3) return spec;
      for (std::size_t k = 0; k < parts.size(); ++k) {
        char* end = nullptr;
        const long v = std::strtol(parts[k].c_str(), &end, 10);
        if (parts[k].empty() || *end != '\0' || v < 0 || v > kMaxArrayIndex) return spec;
        spec.index[k] = static_cast<int>(v);
      }
      spec.element = true;
    }
  }
  spec.valid = true;
  return spec;
}

bool is_location(const Value& v) { return kind_of(v) == Kind::trans || kind_of(v) == Kind::ppoint; }

}  // namespace

// --- the table ---------------------------------------------------------------------------------

const CommandInfo& command_info(Command c) { return kCommands[static_cast<std::size_t>(c)]; }

CommandMatch match_command(std::string_view word) {
  const std::string w = upper(std::string(word));
  if (w.empty()) return {};
  CommandMatch m;
  int found = 0;
  for (std::size_t i = 0; i < kCommands.size(); ++i) {
    const std::string_view name = kCommands[i].name;
    if (name == w) return {Match::found, static_cast<Command>(i)};  // an exact name wins
    if (name.substr(0, w.size()) == w) {
      ++found;
      m.command = static_cast<Command>(i);
    }
  }
  if (found == 1) m.match = Match::found;
  if (found > 1) m = {Match::ambiguous, Command::count};
  return m;
}

// --- formats -----------------------------------------------------------------------------------

std::string format_where(const motion::Location& tool, const robots::JointVector& joints) {
  const motion::Xyzoat x = motion::decompose(tool);
  std::string s = labels(kXyzoat) + '\n' + numbers(x.data(), x.size()) + '\n';
  s += labels(joint_labels(static_cast<std::size_t>(joints.size()))) + '\n';
  s += numbers(joints.data(), static_cast<std::size_t>(joints.size())) + '\n';
  return s;
}

std::string format_location_table(const std::vector<GlobalEntry>& entries) {
  std::size_t width = 16, joints = 0;
  for (const auto& e : entries) {
    if (!is_location(*e.value)) continue;
    width = std::max(width, e.name.size());
    if (const auto* j = std::get_if<robots::JointVector>(e.value)) joints = std::max(joints, static_cast<std::size_t>(j->size()));
  }
  std::string trans, points;
  for (const auto& e : entries) {
    if (const auto* t = std::get_if<motion::Location>(e.value)) {
      const motion::Xyzoat x = motion::decompose(*t);
      trans += fmt::format("{:<{}}", e.name, width) + numbers(x.data(), x.size()) + '\n';
    } else if (const auto* j = std::get_if<robots::JointVector>(e.value)) {
      points += fmt::format("{:<{}}", e.name, width) + numbers(j->data(), static_cast<std::size_t>(j->size())) + '\n';
    }
  }
  std::string s;
  if (!trans.empty()) s += fmt::format("{:<{}}", "Transformation", width) + labels(kXyzoat) + '\n' + trans;
  if (!points.empty()) s += fmt::format("{:<{}}", "Precision point", width) + labels(joint_labels(joints)) + '\n' + points;
  return s;
}

// --- the monitor -------------------------------------------------------------------------------

Monitor::Monitor(Interpreter& interp, motion::Simulator& sim, std::ostream& out)
    : interp_(interp), sim_(sim), out_(out) {
  debugger_.hide(kExecProgram);
  debugger_.hide(kDoProgram);
}

CommandStatus Monitor::execute(const std::string& line) {
  const std::string text = trim(line);
  if (entering_program()) {
    entry_.push_back(line);
    const std::string l = lower(text);
    if (l.rfind(".end", 0) == 0 && (l.size() == 4 || l[4] == ' ' || l[4] == '\t' || l[4] == ';'))
      return finish_entry();
    return CommandStatus::ok;
  }
  typed_ = text;
  if (text.empty() || text[0] == ';') return CommandStatus::ok;
  if (lower(text).rfind(".program", 0) == 0) {  // a program typed line by line until .END
    entry_.push_back(line);
    return CommandStatus::ok;
  }
  std::size_t end = 0;
  while (end < text.size() && std::isalpha(static_cast<unsigned char>(text[end]))) ++end;
  const std::string word = text.substr(0, end);
  const CommandMatch m = match_command(word);
  if (m.match == Match::unknown || m.match == Match::ambiguous) {
    // A V+ command the monitor does not simulate is refused by name, saying why (dialect §13).
    std::size_t full = end;
    while (full < text.size() && (std::isalnum(static_cast<unsigned char>(text[full])) || text[full] == '.')) ++full;
    if (const VplusWord* w = vplus_word(text.substr(0, full), WordKind::monitor))
      return fail(val(Message::not_supported), vplus_refusal(*w));
  }
  if (m.match == Match::unknown) return fail("*Unknown command*", word.empty() ? text : word);
  if (m.match == Match::ambiguous) return fail("*Ambiguous command*", word);
  return dispatch(m.command, trim(std::string_view(text).substr(end)));
}

CommandStatus Monitor::dispatch(Command c, Args rest) {
  const bool no_args = command_info(c).usage.empty();  // the kCommands row shows no argument
  if (no_args && !rest.empty()) return fail(val(Message::syntax), fmt::format("{} takes no argument", command_info(c).name));
  switch (c) {
    case Command::abort:  // with nothing stopped: nothing to do
      interp_.abort();
      if (state_ != ExecState::completed) state_ = ExecState::idle;
      halted_.reset();
      return CommandStatus::ok;
    case Command::calibrate: return CommandStatus::ok;  // no-op in simulation
    case Command::delete_: return cmd_delete(rest);
    case Command::directory: return cmd_directory();
    case Command::do_: return cmd_do(rest);
    case Command::execute: return cmd_execute(rest, false);
    case Command::debug: return cmd_execute(rest, true);
    case Command::bpt: return cmd_bpt(rest, true);
    case Command::nobpt: return cmd_bpt(rest, false);
    case Command::sstep: return cmd_step(DebugMode::over);
    case Command::xstep: return cmd_step(DebugMode::into);
    case Command::help: return cmd_help(rest);
    case Command::here:
      if (rest.empty()) return fail(val(Message::syntax), "HERE needs a variable name");
      return run_instruction("HERE " + rest);
    case Command::listl: case Command::listr: case Command::lists: return cmd_list(rest, c);
    case Command::listp: return cmd_listp(rest);
    case Command::load: return cmd_load(rest);
    case Command::point: return cmd_point(rest);
    case Command::proceed: return cmd_resume(false);
    case Command::retry: return cmd_resume(true);
    case Command::quit: return CommandStatus::quit;
    case Command::speed: return cmd_speed(rest);
    case Command::status: return cmd_status();
    case Command::store: return cmd_store(rest, false);
    case Command::storel: return cmd_store(rest, true);
    case Command::where: out_ << format_where(sim_.here(), sim_.joints()); return CommandStatus::ok;
    case Command::zero: return cmd_zero();
    case Command::count: break;
  }
  return fail("*Unknown command*", typed_);
}

// A monitor command's error: message and detail, then the typed text (dialect §10).
CommandStatus Monitor::fail(std::string message, std::string detail, int column) {
  Diagnostic d;
  d.message = std::move(message);
  d.detail = std::move(detail);
  d.source_line = typed_;
  out_ << format_diagnostic(d);
  if (column > 0) {
    std::string pad = "    ";
    for (int i = 0; i + 1 < column && i < static_cast<int>(typed_.size()); ++i)
      pad += typed_[static_cast<std::size_t>(i)] == '\t' ? '\t' : ' ';
    out_ << pad << "^\n";
  }
  return CommandStatus::failed;
}

CommandStatus Monitor::end_of_input() { return entering_program() ? finish_entry() : CommandStatus::ok; }

// Prints a run's outcome. Errors located in the monitor's own temporary programs are
// reported as command errors (no location line; the typed text instead).
void Monitor::remember(const RunResult& r) {
  state_ = r.status == RunStatus::completed     ? ExecState::completed
         : r.status == RunStatus::collision     ? ExecState::collision
         : r.status == RunStatus::paused        ? ExecState::paused
         : r.status == RunStatus::halted        ? ExecState::halted
         : r.status == RunStatus::interrupted   ? ExecState::interrupted
                                                : ExecState::error;
  state_step_ = r.step;
  state_program_ = r.program;
  tasks_ = r.tasks;
  halted_ = r.interrupt;
  last_run_ = r;
  ++run_count_;
}

void Monitor::record_run(const RunResult& r, const std::string& main) {
  remember(r);
  last_program_ = main;
}

CommandStatus Monitor::report(const RunResult& r, const std::string& shown_name, bool execution) {
  for (const Diagnostic& w : r.warnings) out_ << "Warning: " << format_diagnostic(w);
  Diagnostic d = r.error;
  if (d.program == kDoProgram || d.program == kExecProgram) {
    d.program.clear();
    d.file.clear();
    d.line = d.step = 0;
    d.source_line = typed_;
  }
  if (execution) remember(r);
  switch (r.status) {
    case RunStatus::completed:
      if (execution) out_ << "Program completed: " << shown_name << '\n';
      return CommandStatus::ok;
    case RunStatus::paused:  // PAUSE (PROCEED continues) and HALT are not failures
    case RunStatus::halted: out_ << format_pause(r) << '\n'; return CommandStatus::ok;
    case RunStatus::error:
    case RunStatus::interrupted:
      out_ << format_diagnostic(d) << format_interrupt(r);  // Ctrl-C in a motion: where the arm stopped
      return CommandStatus::failed;
    case RunStatus::collision: {
      const auto& c = r.collision;
      out_ << format_diagnostic(d)
           << fmt::format("at t = {:.6f} s, point ({:.3f}, {:.3f}, {:.3f}) mm\njoints", c.time_s, c.point.x(),
                          c.point.y(), c.point.z());
      for (Eigen::Index i = 0; i < c.joints.size(); ++i) out_ << fmt::format(" {:.3f}", c.joints[i]);
      out_ << '\n';
      return CommandStatus::failed;
    }
  }
  return CommandStatus::failed;
}

// Loads `.PROGRAM name()`, the one statement, `.END` through the normal LOAD path (so every
// name in it is global), runs it and removes it again. A load error comes back in `error`.
Monitor::TemporaryRun Monitor::run_temporary(const char* name, const std::string& statement) {
  Memory& m = interp_.memory();
  const auto diags = interp_.load_source(fmt::format(".PROGRAM {}()\n{}\n.END\n", name, statement), kTypedFile);
  TemporaryRun t;
  for (const Diagnostic& d : diags)
    if (!d.warning && !t.error) t.error = d;
  if (!t.error) t.result = name == std::string(kDoProgram) ? interp_.run_detached(name) : interp_.run(name);
  const auto it = m.symbols.program_slots.find(name);
  if (it != m.symbols.program_slots.end() && static_cast<std::size_t>(it->second) < m.programs.size())
    m.programs[static_cast<std::size_t>(it->second)].reset();
  std::erase(m.load_order, std::string(name));
  return t;
}

// Runs one instruction as the program `do.tmp`.
CommandStatus Monitor::run_instruction(const std::string& instruction) {
  const TemporaryRun t = run_temporary(kDoProgram, instruction);
  if (t.error) {
    // The caret goes under the typed text when it holds the instruction verbatim (DO).
    const bool verbatim = typed_.size() >= instruction.size()
        && typed_.compare(typed_.size() - instruction.size(), instruction.size(), instruction) == 0;
    const int column = verbatim && t.error->line == 2 && t.error->column > 0
        ? static_cast<int>(typed_.size() - instruction.size()) + t.error->column : 0;
    return fail(t.error->message, t.error->detail, column);
  }
  return report(t.result, kDoProgram, false);
}

CommandStatus Monitor::cmd_do(Args rest) {
  if (rest.empty()) return fail(val(Message::syntax), "DO needs an instruction");
  std::size_t end = 0;
  while (end < rest.size() && !std::isspace(static_cast<unsigned char>(rest[end])) && rest[end] != ';') ++end;
  const std::string first = lower(rest.substr(0, end));
  if (std::isdigit(static_cast<unsigned char>(rest[0])) || not_for_do(first))
    return fail(val(Message::syntax), "control flow and declarations are not allowed in DO");
  if (first == "signal") {  // the monitor may also set inputs (dialect §6 [ext])
    std::vector<int> numbers;
    for (const std::string& a : split_list(rest.substr(end))) {
      char* stop = nullptr;
      const long k = std::strtol(a.c_str(), &stop, 10);
      if (a.empty() || *stop != '\0' || std::labs(k) > 100000) {
        numbers.clear();  // not all literals: the evaluator decides (no inputs then)
        break;
      }
      const long v = std::labs(k);
      if (k != 0 && !(v <= 512 || (v >= 1001 && v <= 1512) || (v >= 2001 && v <= 2512)))
        return fail(val(Message::illegal_value), fmt::format("signal {}", k));
      numbers.push_back(static_cast<int>(k));
    }
    if (!numbers.empty()) {
      for (int k : numbers)  // memory and the cell's devices (a conveyor, a logic rule)
        if (const auto loop = interp_.set_signal(k)) return fail("*Device logic loop*", *loop);
      return CommandStatus::ok;
    }
  }
  return run_instruction(rest);
}

CommandStatus Monitor::cmd_execute(Args rest, bool debug) {
  std::string name = rest, args;
  if (const auto open = rest.find('('); open != std::string::npos) {
    if (rest.back() != ')') return fail(val(Message::syntax), "expected \")\"");
    name = trim(rest.substr(0, open));
    args = rest.substr(open + 1, rest.size() - open - 2);
  }
  name = normalize_name(trim(name));
  if (name.empty()) name = last_program_;
  if (name.empty()) return fail(val(Message::undefined_name), "no program executed yet");
  if (!interp_.has_program(name) || name == kDoProgram || name == kExecProgram)
    return fail(val(Message::undefined_name), name);
  last_program_ = name;
  interp_.abort();  // a stopped execution is discarded
  // DEBUG stops before the first step; EXECUTE at a breakpoint, if one is set.
  const DebugMode mode = debug ? DebugMode::into : DebugMode::run;
  if (trim(args).empty())
    return report_driven(debugger_.drive(mode, false, [&] { return interp_.run(name); }), name);
  // Arguments by value: each one in parentheses, CALLed from a one-line program.
  std::string call = "CALL " + name + "(";
  const auto parts = split_list(args);
  for (std::size_t i = 0; i < parts.size(); ++i) call += (i ? ", " : "") + (parts[i].empty() ? "" : "(" + parts[i] + ")");
  std::optional<TemporaryRun> t;
  const RunResult r = debugger_.drive(mode, false, [&] {
    t = run_temporary(kExecProgram, call + ")");
    return t->result;
  });
  if (t->error) return fail(t->error->message, t->error->detail);
  return report_driven(r, name);
}

CommandStatus Monitor::cmd_point(Args rest) {
  const auto eq = rest.find('=');
  const NameSpec spec = parse_name(rest.substr(0, eq));
  if (!spec.valid || spec.whole_array || spec.base[0] == '$')
    return fail(val(Message::syntax), "POINT needs a location name");
  if (eq != std::string::npos) {
    if (trim(rest.substr(eq + 1)).empty()) return fail(val(Message::syntax), "POINT needs a location after \"=\"");
    if (run_instruction("SET " + trim(rest.substr(0, eq)) + " = " + trim(rest.substr(eq + 1))) != CommandStatus::ok)
      return CommandStatus::failed;
  }
  for (const GlobalEntry& e : global_entries(interp_.memory())) {
    if (e.base != spec.base || (e.index != spec.index) || (spec.element != (e.name != e.base))) continue;
    if (!is_location(*e.value)) return fail(val(Message::illegal_value), e.name + " is not a location");
    out_ << format_location_table({e});
    return CommandStatus::ok;
  }
  return fail(val(Message::undefined_value), trim(rest.substr(0, eq)));
}

// LISTL, LISTR, LISTS: the named globals, or all of the command's kind.
CommandStatus Monitor::cmd_list(Args rest, Command which) {
  auto wanted = [which](const Value& v) {
    if (which == Command::listl) return is_location(v);
    return kind_of(v) == (which == Command::listr ? Kind::real : Kind::string);
  };
  const std::vector<GlobalEntry> all = global_entries(interp_.memory());
  std::vector<GlobalEntry> shown;
  const auto names = split_list(rest);
  if (names.empty()) {
    for (const auto& e : all)
      if (wanted(*e.value)) shown.push_back(e);
  }
  for (const std::string& n : names) {
    const NameSpec spec = parse_name(n);
    if (!spec.valid) return fail(val(Message::syntax), "bad name " + n);
    bool any = false;
    for (const auto& e : all) {
      if (e.base != spec.base || (spec.element && (e.index != spec.index || e.name == e.base))) continue;
      if (!wanted(*e.value)) return fail(val(Message::illegal_value), fmt::format("{} is a {}", e.name, kind_name(kind_of(*e.value))));
      shown.push_back(e);
      any = true;
    }
    if (!any) return fail(val(Message::undefined_name), n);
  }
  if (which == Command::listl) {
    out_ << format_location_table(shown);
    return CommandStatus::ok;
  }
  std::size_t width = 16;
  for (const auto& e : shown) width = std::max(width, e.name.size() + 2);
  for (const auto& e : shown) {
    const std::string value = which == Command::listr ? format_number(std::get<double>(*e.value))
                                                      : "\"" + std::get<std::string>(*e.value) + "\"";
    out_ << fmt::format("{:<{}}{}\n", e.name, width, value);
  }
  return CommandStatus::ok;
}

std::vector<std::string> Monitor::sorted_programs() const {
  std::vector<std::string> names = interp_.program_names();
  std::sort(names.begin(), names.end());
  return names;
}

CommandStatus Monitor::cmd_listp(Args rest) {
  std::vector<std::string> names;
  for (const std::string& n : split_list(rest)) {
    const std::string name = normalize_name(n);
    if (!interp_.has_program(name)) return fail(val(Message::undefined_name), n);
    names.push_back(name);
  }
  if (names.empty()) names = sorted_programs();
  const Memory& m = interp_.memory();
  for (const std::string& name : names) {
    const auto& p = m.programs[static_cast<std::size_t>(m.symbols.program_slots.at(name))];
    const std::vector<std::string> lines = program_lines(*p);
    if (lines.empty()) continue;
    out_ << trim(lines.front()) << '\n';
    for (std::size_t i = 1; i + 1 < lines.size(); ++i) out_ << fmt::format("{:>4}  {}\n", i, lines[i]);
    out_ << ".END\n";
  }
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_directory() {
  const Memory& m = interp_.memory();
  for (const std::string& name : sorted_programs()) {
    const auto& p = m.programs[static_cast<std::size_t>(m.symbols.program_slots.at(name))];
    std::string params;
    for (const Param& q : p->params) params += (params.empty() ? "" : ", ") + q.name + (q.array ? "[]" : "");
    out_ << name << '(' << params << ")\n";
  }
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_load(Args rest) {
  if (rest.empty()) return fail(val(Message::syntax), "LOAD needs a file name");
  std::string path = rest;
  if (std::filesystem::path(path).extension().empty()) path += ".v2";
  const collision::InputFile f = collision::classify_input_file(path);
  if (f.missing) return fail("*File not found*", path);
  if (!f.not_regular.empty()) return fail("*Cannot read file*", path + ": " + f.not_regular);
  if (interp_.can_resume()) {  // programs of a stopped execution are not replaced (ABORT first)
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) {
      const std::string t = lower(trim(l));
      if (t.rfind(".program", 0) != 0) continue;
      std::string name = trim(t.substr(8));
      name = normalize_name(name.substr(0, name.find_first_of("( \t;")));
      if (interp_.has_program(name))
        return fail(val(Message::illegal_value), fmt::format("{} would be replaced while an execution is stopped; ABORT first", name));
    }
  }
  Memory& m = interp_.memory();
  const std::vector<std::shared_ptr<const Program>> before = m.programs;
  const auto parse_start = std::chrono::steady_clock::now();
  const auto diags = interp_.load_file(path);
  sim_.recorders().timing.timing.parse_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - parse_start).count();
  bool error = false;
  for (const Diagnostic& d : diags) {
    out_ << (d.warning ? "Warning: " : "") << format_diagnostic(d);
    error = error || !d.warning;
  }
  // With errors the programs that had none are loaded all the same (dialect §8): still a failure.
  for (std::size_t i = 0; i < before.size() && i < m.programs.size(); ++i)
    if (before[i] && m.programs[i] != before[i]) out_ << "Program replaced: " << m.symbols.programs[i] << '\n';
  return error ? CommandStatus::failed : CommandStatus::ok;
}

CommandStatus Monitor::cmd_store(Args rest, bool locations_only) {
  std::size_t end = 0;
  while (end < rest.size() && rest[end] != ',' && !std::isspace(static_cast<unsigned char>(rest[end]))) ++end;
  std::string path = rest.substr(0, end);
  if (path.empty()) return fail(val(Message::syntax), fmt::format("{} needs a file name", locations_only ? "STOREL" : "STORE"));
  if (std::filesystem::path(path).extension().empty()) path += ".v2";
  std::string tail = trim(rest.substr(end));
  if (!tail.empty() && tail[0] == ',') tail = trim(tail.substr(1));
  std::vector<std::string> programs;
  if (locations_only && !tail.empty()) return fail(val(Message::syntax), "STOREL takes only a file name");
  for (const std::string& n : split_list(tail)) {
    const std::string name = normalize_name(n);
    if (!interp_.has_program(name)) return fail(val(Message::undefined_name), n);
    programs.push_back(name);
  }
  if (programs.empty()) programs = interp_.program_names();
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && confirm && !confirm("Replace file? (Y/N) ")) return CommandStatus::ok;
  if (const auto written = write_file_atomic(path, store_text(interp_.memory(), programs, locations_only)); !written)
    return fail("*Cannot write file*", written.error().message);
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_delete(Args rest) {
  const auto names = split_list(rest);
  if (names.empty()) return fail(val(Message::syntax), "DELETE needs a name");
  Memory& m = interp_.memory();
  struct Target {
    bool program = false;
    int slot = -1;
  };
  std::vector<Target> targets;  // checked first: all or nothing
  for (const std::string& n : names) {
    const NameSpec spec = parse_name(n);
    if (!spec.valid || spec.element) return fail(val(Message::syntax), "bad name " + n);
    const bool plain = !spec.whole_array && spec.base[0] != '$' && spec.base[0] != '#';
    if (plain && interp_.has_program(spec.base) && spec.base != kDoProgram) {
      targets.push_back({true, m.symbols.program_slots.at(spec.base)});
      continue;
    }
    const auto it = m.symbols.global_slots.find(spec.base);
    const Variable* v = it == m.symbols.global_slots.end() || static_cast<std::size_t>(it->second) >= m.globals.size()
                            ? nullptr
                            : &m.globals[static_cast<std::size_t>(it->second)];
    if (!v || (!v->scalar && v->elements.empty())) return fail(val(Message::undefined_name), n);
    targets.push_back({false, it->second});
  }
  for (const Target& t : targets) {
    if (t.program) {
      m.programs[static_cast<std::size_t>(t.slot)].reset();
      std::erase(m.load_order, m.symbols.programs[static_cast<std::size_t>(t.slot)]);
    } else {
      m.globals[static_cast<std::size_t>(t.slot)] = Variable{};
    }
  }
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_speed(Args rest) {
  if (rest.empty()) {
    out_ << "Monitor speed: " << format_number(interp_.monitor_speed()) << '\n';
    return CommandStatus::ok;
  }
  char* end = nullptr;
  const double s = std::strtod(rest.c_str(), &end);
  if (end == rest.c_str() || !trim(end).empty()) return fail(val(Message::syntax), "SPEED needs a number");
  if (!(s > 0 && s <= 100)) return fail(val(Message::illegal_value), "SPEED " + rest + " (0 < n <= 100)");
  interp_.set_monitor_speed(s);
  return CommandStatus::ok;
}

namespace {
// STATUS: the run's accuracy and wall time, as in the --report "accuracy" and "timing" objects.
std::string accuracy_line(const motion::Simulator& sim) {
  const motion::RunAccuracy& a = sim.recorders().accuracy.figures;
  const motion::RunTiming& t = sim.recorders().timing.timing;
  const std::string bracket = a.contacts ? fmt::format("{:.3g} s", a.contact_bracket_s) : "none";
  return fmt::format("Accuracy: step <= {:.3g} mm, contact bracket {}, IK residual {:.3g} mm {:.3g} rad, "
                     "line deviation {:.3g} mm {:.3g} rad; wall parse {:.3f} s, preprocessing {:.3f} s, "
                     "motion {:.3f} s, collision {:.3f} s\n",
                     a.step_displacement_mm, bracket, a.ik_residual.position_mm, a.ik_residual.rotation_rad,
                     a.line_deviation.position_mm, a.line_deviation.rotation_rad, t.parse_s, t.preprocess_s,
                     t.motion_s, t.collision_s);
}
}  // namespace

// STATUS: the nearest pair of the clearance report so far (docs/collision.md §12).
static std::string closest_line(const motion::Simulator& sim) {
  const std::string line = format_closest(sim, {});
  return line.empty() ? fmt::format("Closest approach: no pair within {} mm\n",
                                    format_number(sim.recorders().clearance.within_mm))
                      : line;
}

CommandStatus Monitor::cmd_status() {
  auto pose = [](const motion::Location& t) {
    const motion::Xyzoat x = motion::decompose(t);
    return fmt::format("{:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f}", shown3(x[0]), shown3(x[1]), shown3(x[2]),
                       shown3(x[3]), shown3(x[4]), shown3(x[5]));
  };
  std::string state = "idle";
  // The step is named with its program when a CALLed program stopped (step 3 of inner).
  const std::string step = state_program_.empty() || state_program_ == last_program_
      ? fmt::format("step {}", state_step_) : fmt::format("step {} of {}", state_step_, state_program_);
  if (state_ == ExecState::completed) state = "completed";
  if (state_ == ExecState::interrupted) state = fmt::format("interrupted at {}", step);
  if (state_ == ExecState::interrupted && halted_)
    state += fmt::format(", motion of step {} halted at {:.1f} % of its path", halted_->step, 100 * halted_->path_fraction);
  if (state_ == ExecState::paused) state = fmt::format("paused at {}", step);
  if (state_ == ExecState::halted) state = fmt::format("halted at {}", step);
  if (state_ == ExecState::error) state = fmt::format("stopped by error at {}", step);
  if (state_ == ExecState::collision) state = fmt::format("stopped by collision at {}", step);
  const robots::Configuration c = sim_.configuration();
  const robots::ConfigurationRequest& r = sim_.settings().request;
  std::string pending;
  if (r.righty >= 0) pending += r.righty ? " RIGHTY" : " LEFTY";
  if (r.above >= 0) pending += r.above ? " ABOVE" : " BELOW";
  if (r.noflip >= 0) pending += r.noflip ? " NOFLIP" : " FLIP";
  const char* hand = sim_.hand().state == motion::HandState::open ? "OPEN"
                   : sim_.hand().state == motion::HandState::closed ? "CLOSED" : "RELAXED";
  out_ << "Program: " << (last_program_.empty() ? "none" : last_program_) << '\n'
       << "State: " << state << '\n'
       << "Monitor speed: " << format_number(interp_.monitor_speed()) << '\n'
       << "Program speed: " << format_number(interp_.program_speed()) << " ALWAYS"
       << (interp_.next_program_speed() ? ", " + format_number(*interp_.next_program_speed()) + " next motion" : "")
       << '\n'
       << "Configuration: " << (c.righty ? "RIGHTY" : "LEFTY") << ' ' << (c.above ? "ABOVE" : "BELOW") << ' '
       << (c.noflip ? "NOFLIP" : "FLIP") << ' ' << (r.single ? "SINGLE" : "MULTIPLE") << '\n'
       << "Pending configuration: " << (pending.empty() ? "none" : pending.substr(1)) << '\n'
       << "Hand: " << hand << (sim_.hand().pending.has_value() ? " (change pending)" : "") << '\n'
       << "Tool: " << pose(sim_.settings().tool) << '\n'
       << "Base: " << pose(sim_.settings().base) << '\n'
       << "Collision checking: " << (sim_.cell().collision.enabled ? "on" : "off") << '\n'
       << "Clearance: " << format_number(sim_.cell().collision.clearance_mm) << " mm\n"
       << fmt::format("Simulated time: {:.3f} s\n", sim_.time_s()) << accuracy_line(sim_) << closest_line(sim_);
  if (!tasks_.empty()) {  // dialect §7b
    out_ << "Tasks:\n";
    for (const TaskReport& t : tasks_) out_ << fmt::format("  {:>2}  {:<15}  {}\n", t.number, t.program, t.state);
  }
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_resume(bool retry) {
  if (!interp_.can_resume()) return fail("*No program to resume*");
  return report_driven(debugger_.drive(DebugMode::run, true, [&] { return retry ? interp_.retry() : interp_.proceed(); }),
                       last_program_);
}

// --- the program debugger --------------------------------------------------------------------

CommandStatus Monitor::report_driven(const RunResult& r, const std::string& shown_name) {
  if (debugger_.last_stop() == DebugStop::none) return report(r, shown_name, true);
  for (const Diagnostic& w : r.warnings) out_ << "Warning: " << format_diagnostic(w);
  remember(r);
  const StepPlace& p = debugger_.place();
  if (debugger_.last_stop() == DebugStop::breakpoint) out_ << fmt::format("Breakpoint at {}, step {}\n", p.program, p.step);
  out_ << format_step(p) << '\n';
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_step(DebugMode mode) {
  if (!interp_.can_resume()) return fail("*No program to resume*", "DEBUG or EXECUTE a program first");
  return report_driven(debugger_.drive(mode, true, [&] { return interp_.proceed(); }), last_program_);
}

// BPT [[prog,] step] and NOBPT [prog[, step]]. A step alone is in the program stopped (else the
// last one executed); it must hold an instruction, or the breakpoint could never be reached.
CommandStatus Monitor::cmd_bpt(Args rest, bool set) {
  const Memory& m = interp_.memory();
  auto program_of = [&](const std::string& name) -> const Program* {
    const auto it = m.symbols.program_slots.find(name);
    if (it == m.symbols.program_slots.end() || static_cast<std::size_t>(it->second) >= m.programs.size()) return nullptr;
    return m.programs[static_cast<std::size_t>(it->second)].get();
  };
  auto place = [&](const Breakpoint& b) {
    StepPlace s{b.program, b.step, 0, {}, {}, 0};
    if (const Program* p = program_of(b.program)) {
      Diagnostic d;
      locate_at(d, *p, p->line + b.step);
      s.text = trim(d.source_line);
    }
    return s;
  };
  if (rest.empty()) {
    if (!set) {
      debugger_.clear_breakpoints();
      return CommandStatus::ok;
    }
    for (const Breakpoint& b : debugger_.breakpoints()) out_ << format_step(place(b)) << '\n';
    return CommandStatus::ok;
  }
  const auto parts = split_list(rest);
  if (parts.size() > 2) return fail(val(Message::syntax), fmt::format("{} takes a program and a step", set ? "BPT" : "NOBPT"));
  auto number = [](const std::string& t, int& out) {
    char* end = nullptr;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0' || v < 0 || v > 1000000) return false;
    out = static_cast<int>(v);
    return true;
  };
  int step = 0;
  std::string name;
  if (parts.size() == 1 && number(parts[0], step)) {
    name = interp_.can_resume() && !state_program_.empty() ? state_program_ : last_program_;
    if (name.empty()) return fail(val(Message::undefined_name), "no program executed yet; name one");
  } else {
    name = normalize_name(parts[0]);
    if (parts.size() == 2 && !number(parts[1], step)) return fail(val(Message::syntax), "a step number expected");
  }
  const Program* p = name == kDoProgram || name == kExecProgram ? nullptr : program_of(name);
  if (!p) return fail(val(Message::undefined_name), name);
  if (parts.size() == 1 && step == 0) {  // NOBPT prog: all of its breakpoints
    if (set) return fail(val(Message::syntax), "BPT needs a step number");
    debugger_.clear_breakpoints(name);
    return CommandStatus::ok;
  }
  const bool has_code = std::any_of(p->code.begin(), p->code.end(), [&](const Instr& in) { return in.line == p->line + step; });
  if (set && !has_code) return fail(val(Message::illegal_value), fmt::format("no instruction at step {} of {}", step, name));
  if (set) debugger_.set_breakpoint({name, step});
  else if (!debugger_.clear_breakpoint({name, step})) return fail(val(Message::illegal_value), fmt::format("no breakpoint at step {} of {}", step, name));
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_zero() {
  if (confirm && !confirm("Are you sure (Y/N)? ")) return CommandStatus::ok;
  interp_.abort();
  Memory& m = interp_.memory();
  for (auto& p : m.programs) p.reset();
  m.load_order.clear();
  for (auto& v : m.globals) v = Variable{};
  last_program_.clear();
  state_ = ExecState::idle;
  state_step_ = 0;
  state_program_.clear();
  tasks_.clear();
  halted_.reset();
  return CommandStatus::ok;
}

CommandStatus Monitor::cmd_help(Args rest) {
  if (!rest.empty()) {
    const CommandMatch m = match_command(rest);
    if (m.match == Match::unknown) return fail("*Unknown command*", rest);
    if (m.match == Match::ambiguous) return fail("*Ambiguous command*", rest);
    const CommandInfo& c = command_info(m.command);
    out_ << c.name << (c.usage.empty() ? "" : " ") << c.usage << "\n    " << c.help << '\n';
    return CommandStatus::ok;
  }
  for (const CommandInfo& c : kCommands)
    out_ << fmt::format("{:<34}{}\n", fmt::format("{} {}", c.name, c.usage), c.help);
  out_ << fmt::format("{:<34}{}\n", ".PROGRAM name(params)", "enters a program line by line until .END");
  return CommandStatus::ok;
}

// A program typed at the prompt is loaded like a file named "monitor" once its .END arrives.
CommandStatus Monitor::finish_entry() {
  std::string text;
  for (const std::string& l : entry_) text += l + '\n';
  entry_.clear();
  Memory& m = interp_.memory();
  const std::vector<std::shared_ptr<const Program>> before = m.programs;
  bool error = false;
  for (const Diagnostic& d : interp_.load_source(text, kTypedFile)) {
    out_ << (d.warning ? "Warning: " : "") << format_diagnostic(d);
    error = error || !d.warning;
  }
  if (error) return CommandStatus::failed;
  for (std::size_t i = 0; i < before.size() && i < m.programs.size(); ++i)
    if (before[i] && m.programs[i] != before[i]) out_ << "Program replaced: " << m.symbols.programs[i] << '\n';
  return CommandStatus::ok;
}

// --- completion --------------------------------------------------------------------------------

std::vector<std::string> Monitor::completions(const std::string& line, const std::string& word) const {
  const bool lower_case = !word.empty() && std::islower(static_cast<unsigned char>(word.back()));
  auto cased = [&](std::string s) { return lower_case ? lower(std::move(s)) : upper(std::move(s)); };
  std::vector<std::string> out;
  auto offer = [&](const std::string& candidate) {
    if (lower(candidate).rfind(lower(word), 0) == 0 && std::find(out.begin(), out.end(), candidate) == out.end())
      out.push_back(candidate);
  };
  const std::string before = trim(line.substr(0, line.size() - std::min(line.size(), word.size())));
  if (before.empty()) {  // the command word
    for (const CommandInfo& c : kCommands) offer(cased(std::string(c.name)));
    return out;
  }
  std::size_t end = 0;
  while (end < before.size() && std::isalpha(static_cast<unsigned char>(before[end]))) ++end;
  const CommandMatch m = match_command(before.substr(0, end));
  const Command c = m.match == Match::found ? m.command : Command::count;
  const bool instruction_word = c == Command::do_ && trim(before.substr(end)).empty();
  if (instruction_word)
    for (const std::string& k : do_words()) offer(cased(k));
  const bool programs = c == Command::execute || c == Command::listp || c == Command::delete_
      || c == Command::store || c == Command::do_;
  if (programs)
    for (const std::string& p : sorted_programs()) offer(p);
  const bool variables = c == Command::do_ || c == Command::here || c == Command::point || c == Command::listl
      || c == Command::listr || c == Command::lists || c == Command::delete_ || c == Command::execute;
  if (variables) {
    const Memory& m2 = interp_.memory();
    for (const std::string& g : m2.symbols.globals)
      if (g.find('@') == std::string::npos) offer(g);
  }
  return out;
}

}  // namespace asimov::interpreter
