#include "evaluator.hpp"

#include "errors.hpp"
#include "limits.hpp"
#include "operators.hpp"
#include "terminal.hpp"
#include "asimov/motion/targets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>

namespace asimov::interpreter {
namespace {

using ast::Op;

}  // namespace

Evaluator::Evaluator(motion::Simulator& sim, std::ostream& out, Memory& memory, const Limits& limits)
    : sim_(sim), out_(out), memory_(memory), limits_(limits), cell_(sim, memory), arm_(sim, memory, cell_, *this),
      sched_(*this, arm_, cell_, sim, memory, limits), files_(*this) {}

RunResult Evaluator::run(int slot, bool resumable) {
  std::optional<Stopped> earlier = std::move(stopped_);  // a run keeps a stopped execution
  stopped_.reset();
  stack_.clear();
  arm_.begin_run();
  current_program_ = nullptr;
  current_line_ = 0;
  sched_.begin_execution();
  RunResult r = protected_run(memory_.symbols.programs[static_cast<std::size_t>(slot)], [&] {
    const auto& program = memory_.programs.at(static_cast<std::size_t>(slot));
    if (!program) return stop(fault(Message::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(slot)]));
    if (!program->executable) return stop(fault(Message::not_executable, program->name));
    stack_.push_top(*program);
    return RunStatus::completed;
  });
  if (!resumable) {
    stopped_.reset();
    if (r.interrupt) sim_.drop_halted_motion();  // a DO's halted motion is not resumed either
  }
  if (!stopped_) stopped_ = std::move(earlier);  // only the latest stopped execution is kept
  return r;
}

bool Evaluator::can_resume() const { return stopped_.has_value(); }

void Evaluator::abort() {
  if (stopped_ && stopped_->motion_halted) sim_.drop_halted_motion();
  stopped_.reset();
}

RunResult Evaluator::resume(bool retry) {
  if (!stopped_) {
    RunResult r;
    r.status = RunStatus::error;
    r.error.message = "*No program to resume*";
    return r;
  }
  Stopped s = std::move(*stopped_);
  stopped_.reset();
  stack_.assign(std::move(s.stack));
  arm_.begin_resume(s.arm, s.motion);
  resumed_pins_ = std::move(s.pinned);
  RunResult r = protected_run(s.program, [&] {
    // After Ctrl-C halted a motion, PROCEED and RETRY first carry out its rest (a real
    // controller resumes the interrupted motion towards its target).
    if (s.motion_halted)
      if (const RunStatus st = arm_.resume_halted_motion(); st != RunStatus::completed) return st;
    // After a collision the step that found the contact runs again (PROCEED and RETRY);
    // RETRY after an error re-runs the failing step; PROCEED after an error skips it.
    // After PAUSE both continue with the next step.
    // After Ctrl-C (or PAUSE) both run the step not yet run.
    if (s.status == RunStatus::paused || s.status == RunStatus::interrupted) return RunStatus::completed;
    if (!stack_.empty() && (retry || s.status == RunStatus::collision)) --stack_.back().pc;
    if (retry && s.status == RunStatus::collision && arm_.last_motion()) return arm_.start_motion(*arm_.last_motion());
    return RunStatus::completed;
  });
  resumed_pins_.clear();  // a new stop took what it needs (pin_programs)
  return r;
}

// Every program a stopped execution's frames may point to: memory_'s, and those a resumed
// execution still runs that memory_ has dropped since.
std::vector<std::shared_ptr<const Program>> Evaluator::pin_programs() const {
  std::vector<std::shared_ptr<const Program>> pins = memory_.programs;
  for (const auto& p : resumed_pins_)
    if (p && std::find(memory_.programs.begin(), memory_.programs.end(), p) == memory_.programs.end()) pins.push_back(p);
  return pins;
}

// --- the protected boundary -----------------------------------------------------------------

RunResult Evaluator::protected_run(const std::string& name, const std::function<RunStatus()>& setup) {
  RunResult result;
  warnings_.clear();
  arm_.begin_records();
  // The simulator reads the Ctrl-C flag and asks the REACTI stop condition while this run goes
  // on, and only then.
  struct InterruptWiring {
    motion::Simulator& sim;
    ~InterruptWiring() {
      sim.set_interrupt(nullptr);
      sim.set_stop_condition(nullptr);
    }
  } wiring{sim_};
  sim_.set_interrupt(limits_.interrupt);
  sim_.set_stop_condition([this](double t, const robots::JointVector&) { return sched_.brake_now(t); });
  sim_.settings().continuous_path = memory_.settings.cp;  // ENABLE / DISABLE CP (docs/blending.md)
  files_.begin_run(limits_);
  struct FileClosing {  // what was written is committed however the run ends
    FileStatements& files;
    ~FileClosing() { files.end_run(); }
  } closing{files_};
  memory_.globals.resize(memory_.symbols.globals.size());
  globals_.resize(memory_.globals.size());  // no global is added while a run goes on
  for (std::size_t i = 0; i < globals_.size(); ++i) globals_[i] = &memory_.globals[i];
  ctx_.globals = globals_.data();
  ctx_.slots = nullptr;

  auto locate = [&](Diagnostic& d, const Program* p, int line) {
    if (!p) return;
    locate_at(d, *p, line);
    result.program = p->name;
    result.line = line;
    result.step = d.step;
  };
  auto collided = [&](const motion::CollisionReport& report) {
    result = RunResult{};
    result.status = RunStatus::collision;
    result.collision = report;
    result.error.message = "*Collision*";
    result.error.detail = report.body_a + " / " + report.body_b;
    locate(result.error, arm_.motion_program(), arm_.motion_line());
  };

  run_program_ = name;
  sched_.begin_run();
  struct TaskReset {  // the tasks of this run end with it (a stopped run resumes task 0 only)
    Scheduler& tasks;
    ~TaskReset() { tasks.drop_tasks(); }
  } task_reset{sched_};
  const auto guarded = [this](const std::function<RunStatus()>& part) {
    try {
      return part();
    } catch (Fault& e) {  // raise(): a VAL error found while evaluating a statement
      return stop(std::move(e));
    } catch (const Braked&) {  // a REACTI stopped the motion outside a step: the run goes on
      return RunStatus::completed;
    }
  };
  RunStatus status = guarded(setup);
  // An error that a REACTE traps calls the trap program and the run goes on (dialect §7c).
  for (bool again = status == RunStatus::completed; again;) {
    status = guarded([this] { return sched_.run_tasks(); });
    if (status == RunStatus::completed)
      status = guarded([this] { return arm_.finish_motion(); });  // the last motion completes at the end
    again = status == RunStatus::error && sched_.trap_error(fault_);
  }
  if (status == RunStatus::error || status == RunStatus::interrupted) {
    result.status = status;
    result.error.message = fault_.message;
    result.error.detail = fault_.detail;
    locate(result.error, current_program_, current_line_);
    // The motion already started still completes (forward processing); contact wins. After
    // Ctrl-C (the flag is still set) it stops at once, where it is, and its rest is kept.
    try {
      if (sim_.motion_pending()) {
        const motion::MotionResult r = sim_.finish_motion();
        if (r.status == motion::MotionStatus::collision) collided(r.collision);
        if (r.status == motion::MotionStatus::interrupted && r.interrupt.by_condition) sched_.braked(r.interrupt);
        else if (r.status == motion::MotionStatus::interrupted) arm_.set_halted(r.interrupt);
      }
    } catch (...) {
    }
  } else if (status == RunStatus::collision) {
    collided(arm_.contact());
  } else if (status == RunStatus::paused || status == RunStatus::halted) {
    result.status = status;
    locate(result.error, current_program_, current_line_);
    result.error = Diagnostic{};
    if (status == RunStatus::halted) stack_.clear();  // HALT cannot be resumed
  }
  if (result.status == RunStatus::error || result.status == RunStatus::interrupted || result.status == RunStatus::collision)
    memory_.last_error = error_code(result.error.message);  // what ERROR() returns from now on
  sched_.end_run(result, current_program_, current_line_);  // the tasks for STATUS (dialect §7b)
  if (sched_.has_tasks()) stack_.clear();  // with tasks the run cannot be resumed
  if (result.status == RunStatus::completed) {
    result.program = name;
    result.line = result.step = 0;
  } else if (!stack_.empty() || (!sched_.has_tasks() && result.status == RunStatus::collision) || arm_.halted()) {
    stopped_ = Stopped{stack_.take(), result.status, name, arm_.settings(), arm_.last_motion(),
                       arm_.halted().has_value(), pin_programs()};
  }
  stack_.clear();
  result.warnings = std::move(warnings_);
  warnings_.clear();
  arm_.end_records(result);  // interrupt, motion times and sites
  return result;
}

// --- statements -----------------------------------------------------------------------------

// The dispatch loop. The statements that dominate loops (real assignments, jumps, FOR steps)
// run inline here through their compiled expressions; any value the compiled form does not
// handle, and every other statement, goes through execute(), which raises the exact errors.
RunStatus Evaluator::loop() {
  const std::atomic<bool>* interrupt = limits_.interrupt;
  const std::uint64_t max_statements = limits_.max_statements;
  const bool hooked = sched_.hooked();  // the debugger's, tested once per instruction
  StepBudget& budget = sched_.budget();
  while (!stack_.empty()) {
    Frame& f = stack_.back();  // valid until a CALL, RETURN or STOP changes the stack
    const Program& program = *f.program;
    const Instr* const code = program.code.data();
    const int size = static_cast<int>(program.code.size());
    current_program_ = &program;
    ctx_.slots = f.params.data();  // every evaluation happens below, in this frame
    for (;;) {
      if (f.pc >= size) {  // .END returns
        pop_frame();
        break;
      }
      // Reactions (dialect §7c) are looked at between steps: one due is called before this step.
      if (!sched_.reactions().empty()) {
        bool pushed = false;
        if (const RunStatus s = sched_.react(pushed); s != RunStatus::completed) return s;
        if (pushed) break;
      }
      const Instr& in = code[f.pc];
      current_line_ = in.line;
      // Ctrl-C: stop before this step, which PROCEED and RETRY then run.
      if (interrupt && interrupt->load(std::memory_order_relaxed)) return stop(fault(Message::interrupted));
      if (hooked) [[unlikely]]
        if (const RunStatus s = sched_.at_step(in, f); s != RunStatus::completed) return s;
      ++f.pc;
      if (++budget.done > budget.until) {  // this execution's steps (a run or a resumption)
        if (budget.until >= max_statements)
          return stop(fault(Message::too_many_statements, fmt::format("more than {}", max_statements)));
        --f.pc;  // the task's time slice is used up: the step runs when it comes back
        sched_.slice_used();
        return RunStatus::completed;
      }
      double x;
      switch (in.code) {
        case Code::assign:
          if (in.real_target && in.fast0 && run_root(in.fast0, ctx_, x)) {
            const Node& t = in.target;
            if (!t.subscripted) {  // a scalar that holds a real: written in place
              Variable& v = *(t.ref.scope == Scope::global ? ctx_.globals : ctx_.slots)[t.ref.slot];
              if (v.scalar)  // never with elements (see real_of)
                if (double* d = std::get_if<double>(&*v.scalar)) {
                  *d = x;
                  continue;
                }
            }
            if (!store_in_place(t, x)) store_real(t, x);
            continue;
          }
          break;
        case Code::jump:
          f.pc = in.jump;
          continue;
        case Code::jump_false:
          if (in.fast0 && run_root(in.fast0, ctx_, x)) {
            if (x == 0) f.pc = in.jump;
            continue;
          }
          break;
        case Code::jump_true:
          if (in.fast0 && run_root(in.fast0, ctx_, x)) {
            if (x != 0) f.pc = in.jump;
            continue;
          }
          break;
        case Code::for_next: {
          Variable& v = variable(in.target);
          if (!v.scalar) break;  // never with elements (see real_of)
          double* d = std::get_if<double>(&*v.scalar);
          if (!d) break;
          const double step = f.temps[static_cast<std::size_t>(in.temp) + 1];
          *d = finite(*d + step);
          if (step > 0 ? *d <= f.temps[static_cast<std::size_t>(in.temp)] : *d >= f.temps[static_cast<std::size_t>(in.temp)])
            f.pc = in.jump;
          continue;
        }
        default: break;
      }
      RunStatus s = RunStatus::completed;
      try {
        s = execute(in);
      } catch (const Braked&) {  // a REACTI stopped the motion this step waited for
        f.pc = static_cast<int>(&in - code);  // it runs again once the reaction is served
        continue;
      }
      if (s != RunStatus::completed) return s;
      if (sched_.tasks_running() && sched_.gives_way()) return RunStatus::completed;  // tasks (dialect §7b)
      if (in.code == Code::call || in.code == Code::calls || in.code == Code::return_ || in.code == Code::stop) break;
    }
  }
  return RunStatus::completed;
}

RunStatus Evaluator::stop(Fault f) {
  fault_ = std::move(f);
  return fault_.kind == Message::interrupted ? RunStatus::interrupted : RunStatus::error;
}

// The statements that can end a run (they wait for or start a motion, or pause); every other
// one goes on in statement().
RunStatus Evaluator::execute(const Instr& in) {
  switch (in.code) {
#define ASIMOV_MOTION(kw, ...) case Code::kw:
#include "instructions.def"
      return arm_.motion(in);
    case Code::hand: return arm_.hand(in);
    case Code::wait: case Code::wait_event: return sched_.wait(in);
    case Code::break_: return arm_.finish_motion();
    case Code::pause: case Code::halt:  // PAUSE and HALT wait for the motion
      if (const RunStatus s = arm_.finish_motion(); s != RunStatus::completed) return s;
      return in.code == Code::halt ? RunStatus::halted : RunStatus::paused;
    default:
      statement(in);
      return RunStatus::completed;
  }
}

void Evaluator::statement(const Instr& in) {
  Frame& f = stack_.back();
  switch (in.code) {
    case Code::assign: {
      if (double x; in.args[0].plain && in.target.text[0] != '$' && in.target.text[0] != '#'
                    && (run_fast(in.args[0], ctx_, x) || try_real(in.args[0], x)))
        return store_real(in.target, x);
      Value v = eval(in.args[0]);
      const char prefix = in.target.text[0];
      if (prefix == '$') {
        to_string_value(v);
      } else if (kind_of(v) == Kind::trans || kind_of(v) == Kind::ppoint) {
        raise(Message::illegal_value, "a location is assigned with SET");
      } else if (prefix == '#' || kind_of(v) != Kind::real) {
        raise(Message::illegal_value, fmt::format("{} cannot hold a {}", in.target.text, kind_name(kind_of(v))));
      }
      store(in.target, std::move(v));
      return;
    }
    case Code::set: {
      Value v = eval(in.args[0]);
      const Kind want = in.target.text[0] == '#' ? Kind::ppoint : Kind::trans;
      if (in.target.text[0] == '$' || kind_of(v) != want)
        raise(Message::illegal_value, fmt::format("{} cannot hold a {}", in.target.text, kind_name(kind_of(v))));
      store(in.target, std::move(v));
      return;
    }
    case Code::here:
      if (in.target.text[0] == '$') raise(Message::illegal_value, "HERE needs a location variable");
      if (in.target.text[0] == '#') store(in.target, sim_.joints());
      else store(in.target, finite_location(sim_.here()));  // huge BASE/TOOL may overflow
      return;
    case Code::decompose: {
      const Value v = eval(in.args[0]);
      std::vector<double> parts;
      if (const auto* j = std::get_if<robots::JointVector>(&v)) {
        parts.assign(j->data(), j->data() + j->size());
      } else {
        const motion::Xyzoat x = motion::decompose(as_pose(v, sim_));
        parts.assign(x.begin(), x.end());
      }
      if (in.target.text[0] == '$' || in.target.text[0] == '#')
        raise(Message::illegal_value, "DECOMPOSE needs a real array");
      Variable& var = variable(in.target);
      if (var.scalar) raise(Message::illegal_value, fmt::format("{} is not an array", in.target.text));
      // a[] (no index): from a[0]; a[k]: from a[k] (the last index counts up).
      Index idx = in.target.subscripted && !in.target.kids.empty() ? index(in.target) : Index{0, 0, 0};
      const std::size_t last = in.target.kids.empty() ? 0 : in.target.kids.size() - 1;
      for (double p : parts) {
        if (idx[last] > kMaxArrayIndex) raise(Message::illegal_value, "index above 65535");
        var.elements.set(idx, p);
        ++idx[last];
      }
      return;
    }
    case Code::type: {
      std::vector<Value> values;
      values.reserve(in.args.size());
      for (const Node& n : in.args) values.push_back(eval(n));
      bool newline = true;
      out_ << format_items(in.formats, values, newline);
      if (newline) out_ << '\n';
      return;
    }
#define ASIMOV_MOTION(kw, ...) case Code::kw:
#include "instructions.def"
    case Code::hand: case Code::wait: case Code::wait_event: case Code::break_: case Code::pause: case Code::halt:
      return;  // execute()
    case Code::signal:  // SIGNAL n, ...: n > 0 on, n < 0 off, 0 ignored
      for (const Node& n : in.args) {
        cell_.set_signal(signal_number(n, true), current_line_);
      }
      return;
    case Code::accel: case Code::duration: case Code::tool: case Code::base: case Code::configure: case Code::speed:
      return arm_.setting(in);
    case Code::timer: {
      const int k = to_index(to_real(eval(in.args[0]), "timer number"));
      if (k < 1 || k > 16) raise(Message::illegal_value, fmt::format("timer {}", k));
      memory_.timers[static_cast<std::size_t>(k)] = {to_real(eval(in.args[1]), "TIMER value"), sim_.time_s()};
      return;
    }
    case Code::unsupported:
      if (!in.warn_only) raise(Message::not_supported, in.target.text);
      return warn_once(in.target.text, in);
    case Code::io: return files_.execute(in);
    case Code::execute: return sched_.execute_task(in);
    case Code::task: return sched_.task_instruction(in);
    case Code::robot: return sched_.robot_attach(in.io == IoOp::attach);
    case Code::react: case Code::reacte: case Code::ignore: case Code::lock: return sched_.reaction_instruction(in);
    case Code::prompt: return prompt(in);
    case Code::parameter:  // PARAMETER name = value
      return set_parameter(in.target.text, to_real(eval(in.args[0]), "PARAMETER value"), memory_.settings, sim_);
    case Code::enable: case Code::disable:  // ENABLE / DISABLE switch, ...
      for (const Node& n : in.args)
        if (!set_switch(n.text, in.code == Code::enable, memory_.settings, sim_))
          warn_once((in.code == Code::enable ? "ENABLE " : "DISABLE ") + n.text, in);
      return;
    case Code::case_init:
      f.temps[static_cast<std::size_t>(in.temp)] = to_real(eval(in.args[0]), "CASE value");
      return;
    case Code::case_test: {
      const double value = f.temps[static_cast<std::size_t>(in.temp)];
      for (const Node& n : in.args)
        if (to_real(eval(n), "VALUE") == value) return;
      f.pc = in.jump;
      return;
    }
    case Code::jump: f.pc = in.jump; return;
    case Code::jump_false:
      if (real(in.args[0], "condition") == 0) f.pc = in.jump;
      return;
    case Code::jump_true:
      if (real(in.args[0], "condition") != 0) f.pc = in.jump;
      return;
    case Code::for_init: {
      const double from = real(in.args[0], "FOR start");
      const double to = real(in.args[1], "FOR limit");
      const double step = in.args.size() > 2 ? real(in.args[2], "FOR step") : 1.0;
      if (step == 0) raise(Message::illegal_value, "FOR with STEP 0");
      store(in.target, from);
      f.temps[static_cast<std::size_t>(in.temp)] = to;
      f.temps[static_cast<std::size_t>(in.temp) + 1] = step;
      if (step > 0 ? !(from <= to) : !(from >= to)) f.pc = in.jump;
      return;
    }
    case Code::for_next: {
      const double to = f.temps[static_cast<std::size_t>(in.temp)];
      const double step = f.temps[static_cast<std::size_t>(in.temp) + 1];
      const double v = finite(real(in.target, "FOR variable") + step);
      store_real(in.target, v);
      if (step > 0 ? v <= to : v >= to) f.pc = in.jump;
      return;
    }
    case Code::call: case Code::calls: return call(in);
    case Code::return_: pop_frame(); return;
    case Code::stop: stack_.clear(); return;
  }
}

void Evaluator::call(const Instr& in) {
  int slot = in.program;
  if (in.code == Code::calls) {  // CALLS: the program the string names, looked up now
    const std::string name = normalize_name(to_string_value(eval(in.target)));
    const auto found = memory_.symbols.program_slots.find(name);
    if (found == memory_.symbols.program_slots.end() || static_cast<std::size_t>(found->second) >= memory_.programs.size()
        || !memory_.programs[static_cast<std::size_t>(found->second)])
      raise(Message::undefined_name, name.empty() ? "\"\" (CALLS)" : name);
    slot = found->second;
  }
  const auto& program = memory_.programs[static_cast<std::size_t>(slot)];
  if (!program) raise(Message::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(slot)]);
  if (!program->executable) raise(Message::not_executable, program->name);
  if (static_cast<int>(stack_.size()) >= limits_.max_call_depth)
    raise(Message::too_many_calls, fmt::format("{} levels", stack_.size()));
  if (in.args.size() > program->params.size())
    raise(Message::illegal_value, fmt::format("{} takes {} arguments", program->name, program->params.size()));
  Frame& frame = stack_.next();  // pushed once the arguments are evaluated in the caller's frame
  frame.program = program.get();
  // Variables owned by the frame: those of an earlier call, emptied when it returned (no
  // construction per CALL), then new ones. Reserved first: the pointers taken stay valid.
  const std::size_t slots = program->params.size() + program->autos.size();
  frame.owned.reserve(slots);
  frame.params.reserve(slots);
  std::size_t used = 0;
  auto fresh = [&]() -> Variable& {
    if (used == frame.owned.size()) {
      ++used;
      return frame.owned.emplace_back();
    }
    Variable& v = frame.owned[used++];
    v.scalar.reset();  // already empty unless an earlier CALL failed while filling this frame
    if (!v.elements.empty()) v.elements = Elements{};
    return v;
  };
  for (std::size_t i = 0; i < program->params.size(); ++i) {
    const bool given = i < in.args.size() && in.args[i].kind != NodeKind::absent;
    if (given && in.by_ref[i]) {
      frame.params.push_back(&variable(in.args[i]));  // the caller's variable itself
      continue;
    }
    Variable& owned = fresh();
    if (double x; given && run_fast(in.args[i], ctx_, x)) owned.scalar.emplace(x);
    else if (given) owned.scalar = eval(in.args[i]);
    frame.params.push_back(&owned);
  }
  for (std::size_t i = 0; i < program->autos.size(); ++i)  // a fresh AUTO copy per call
    frame.params.push_back(&fresh());
  frame.temps.resize(static_cast<std::size_t>(program->temps));
  stack_.commit();
}

void Evaluator::pop_frame() {
  Frame& f = stack_.back();
  if (f.restore_priority >= 0) sched_.reactions().set_priority(f.restore_priority);  // a reaction's RETURN
  if (f.trap) sched_.reactions().trapping = false;
  f.program = nullptr;
  f.params.clear();
  for (Variable& v : f.owned) {  // emptied, kept for the next CALL
    v.scalar.reset();
    if (!v.elements.empty()) v.elements = Elements{};
  }
  f.temps.clear();
  f.pc = 0;
  stack_.pop();
}

// --- waiting, terminal input, settings -------------------------------------------------------

// PROMPT text, variable: prints the text and reads one line into a string or a real.
void Evaluator::prompt(const Instr& in) {
  const std::string text = to_string_value(eval(in.args[0]));
  std::istream& input = in_ ? *in_ : std::cin;
  const bool string_target = in.target.text[0] == '$';
  for (;;) {
    out_ << text;
    out_.flush();
    std::string line;
    if (!read_reply(input, line)) {
      out_ << '\n';
      raise(Message::illegal_value, "end of input at PROMPT");
    }
    if (!interactive_) out_ << '\n';  // the reply is not echoed: keep the output in lines
    if (string_target) {
      if (line.size() > kMaxStringLength) raise(Message::illegal_value, "string longer than 128 characters");
      return store(in.target, line);
    }
    if (const auto v = parse_reply_number(line)) return store(in.target, *v);
    if (!interactive_) raise(Message::illegal_value, fmt::format("\"{}\" is not a number", line));
  }
}

// A V+ construct that the simulation ignores (dialect §7): one warning per execution.
void Evaluator::warn_once(const std::string& keyword, const Instr& in) {
  for (const Diagnostic& w : warnings_)
    if (w.detail == keyword) return;
  Diagnostic w;
  w.message = std::string(message_text(Message::not_supported));
  w.detail = keyword;
  w.warning = true;
  locate_at(w, *current_program_, in.line);
  warnings_.push_back(std::move(w));
}

}  // namespace asimov::interpreter
