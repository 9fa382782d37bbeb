#include "asimov/interpreter/debugger.hpp"

#include "evaluator.hpp"

#include <fmt/format.h>

namespace asimov::interpreter {

void Debugger::clear_breakpoints(const std::string& program) {
  std::erase_if(breakpoints_, [&](const Breakpoint& b) { return b.program == program; });
}

RunResult Debugger::drive(DebugMode mode, bool resuming, const std::function<RunResult()>& call) {
  mode_ = mode;
  // A step resumed runs before the next stop. PROCEED passes over only a stop of its own (a
  // breakpoint there); after PAUSE, an error or Ctrl-C a breakpoint on the next step holds.
  skip_first_ = resuming && (mode != DebugMode::run || held_);
  held_ = false;
  origin_depth_ = 0;
  prev_program_ = nullptr;
  stop_ = DebugStop::none;
  place_ = StepPlace{};
  if (mode == DebugMode::run && breakpoints_.empty()) return call();  // full speed: no hook
  struct Unhook {  // the hook lives as long as this run, whatever ends it
    Interpreter& interp;
    ~Unhook() { interp.set_step_hook({}); }
  } unhook{interp_};
  interp_.set_step_hook([this](const StepEvent& e) { return on_step(e); });
  RunResult r = call();
  // Only a pause this hook asked for is the debugger's (PAUSE in the program is not).
  if (r.status != RunStatus::paused) stop_ = DebugStop::none;
  held_ = stop_ != DebugStop::none;
  return r;
}

StepAction Debugger::on_step(const StepEvent& e) {
  if (hidden_.count(e.program)) return StepAction::go;
  // A step starts where the program, the depth or the line changes, or where the same line
  // runs again (a jump back to it).
  const bool starts = !prev_program_ || prev_program_ != &e.program || prev_depth_ != e.depth
      || prev_line_ != e.line || e.instruction <= prev_instruction_;
  prev_program_ = &e.program;
  prev_depth_ = e.depth;
  prev_line_ = e.line;
  prev_instruction_ = e.instruction;
  if (skip_first_) {  // the step resumed: it runs; SSTEP counts depth from it
    skip_first_ = false;
    origin_depth_ = e.depth;
    return StepAction::go;
  }
  if (!starts || !e.pausable) return StepAction::go;
  if (origin_depth_ == 0) origin_depth_ = e.depth;
  DebugStop why = DebugStop::none;
  if (breakpoints_.count(Breakpoint{e.program, e.step})) why = DebugStop::breakpoint;
  else if (mode_ == DebugMode::into || (mode_ == DebugMode::over && e.depth <= origin_depth_)) why = DebugStop::step;
  if (why == DebugStop::none) return StepAction::go;
  stop_ = why;
  place_ = StepPlace{e.program, e.step, e.line, {}, {}, e.depth};
  const Memory& m = interp_.memory();
  if (const auto it = m.symbols.program_slots.find(e.program); it != m.symbols.program_slots.end()
      && static_cast<std::size_t>(it->second) < m.programs.size() && m.programs[static_cast<std::size_t>(it->second)]) {
    Diagnostic d;
    locate_at(d, *m.programs[static_cast<std::size_t>(it->second)], e.line);
    place_.file = d.file;
    place_.text = d.source_line.substr(std::min(d.source_line.size(), d.source_line.find_first_not_of(" \t")));
  }
  return StepAction::pause;
}

std::optional<Breakpoint> step_at_line(Interpreter& interp, const std::string& file, int line) {
  for (const auto& p : interp.memory().programs)
    if (p && p->file == file && line > p->line)
      for (const Instr& in : p->code)
        if (in.line == line) return Breakpoint{p->name, line - p->line};
  return std::nullopt;
}

std::string format_step(const StepPlace& p) { return fmt::format("{}, step {}:  {}", p.program, p.step, p.text); }

}  // namespace asimov::interpreter
