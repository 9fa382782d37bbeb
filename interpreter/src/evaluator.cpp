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
    : sim_(sim), out_(out), memory_(memory), limits_(limits) {}

RunResult Evaluator::run(int slot, bool resumable) {
  std::optional<Stopped> earlier = std::move(stopped_);  // a run keeps a stopped execution
  stopped_.reset();
  stack_.clear();
  speed_always_ = 100;  // each execution starts with SPEED 100 ALWAYS
  speed_next_.reset();
  duration_always_ = 0;  // and no DURATION
  duration_next_.reset();
  current_program_ = nullptr;
  current_line_ = 0;
  bare_wait_end_ = -1;
  motion_program_ = nullptr;
  last_motion_.reset();
  reactions0_ = Reactions{};  // reactions, priority and trap are the execution's (dialect §7c)
  RunResult r = protected_run(memory_.symbols.programs[static_cast<std::size_t>(slot)], [&] {
    const auto& program = memory_.programs.at(static_cast<std::size_t>(slot));
    if (!program) return stop(fault(Message::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(slot)]));
    if (!program->executable) return stop(fault(Message::not_executable, program->name));
    Frame& top = stack_.next();
    top.program = program.get();
    top.owned.clear();
    top.owned.resize(program->params.size() + program->autos.size());
    for (Variable& v : top.owned) top.params.push_back(&v);
    top.temps.resize(static_cast<std::size_t>(program->temps));
    stack_.commit();
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
  speed_always_ = s.speed_always;
  speed_next_ = s.speed_next;
  duration_always_ = s.duration_always;
  duration_next_ = s.duration_next;
  last_motion_ = s.motion;
  resumed_pins_ = std::move(s.pinned);
  RunResult r = protected_run(s.program, [&] {
    // After Ctrl-C halted a motion, PROCEED and RETRY first carry out its rest (a real
    // controller resumes the interrupted motion towards its target).
    if (s.motion_halted)
      if (const RunStatus st = resume_halted_motion(); st != RunStatus::completed) return st;
    // After a collision the step that found the contact runs again (PROCEED and RETRY);
    // RETRY after an error re-runs the failing step; PROCEED after an error skips it.
    // After PAUSE both continue with the next step.
    // After Ctrl-C (or PAUSE) both run the step not yet run.
    if (s.status == RunStatus::paused || s.status == RunStatus::interrupted) return RunStatus::completed;
    if (!stack_.empty() && (retry || s.status == RunStatus::collision)) --stack_.back().pc;
    if (retry && s.status == RunStatus::collision && last_motion_) return start_motion(*last_motion_);
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
  motion_sites_.clear();
  motion_times_.clear();
  motion_times_omitted_ = 0;
  halt_.reset();
  reaction_stops_.clear();
  brake_signal_ = 0;
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
  sim_.set_stop_condition([this](double t, const robots::JointVector&) { return brake_now(t); });
  sim_.settings().continuous_path = memory_.settings.cp;  // ENABLE / DISABLE CP (docs/blending.md)
  files_.set_root(limits_.files_root);
  files_.set_limits({limits_.max_record_bytes, limits_.max_file_bytes});
  struct FileClosing {  // what was written is committed however the run ends
    FileUnits& files;
    ~FileClosing() { files.close_all(); }
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
    locate(result.error, motion_program_, motion_line_);
  };

  run_program_ = name;
  statements_ = 0;
  budget_ = limits_.max_statements;
  robot_task_ = 0;
  struct TaskReset {  // the tasks of this run end with it (a stopped run resumes task 0 only)
    Evaluator& e;
    ~TaskReset() {
      e.tasks_.clear();
      e.running_ = nullptr;
    }
  } task_reset{*this};
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
    status = guarded([this] { return run_tasks(); });
    if (status == RunStatus::completed)
      status = guarded([this] { return finish_motion(); });  // the last motion completes at the end
    again = status == RunStatus::error && trap_error();
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
        if (r.status == motion::MotionStatus::interrupted && r.interrupt.by_condition) braked(r.interrupt);
        else if (r.status == motion::MotionStatus::interrupted) halt_ = r.interrupt;
      }
    } catch (...) {
    }
  } else if (status == RunStatus::collision) {
    collided(contact_);
  } else if (status == RunStatus::paused || status == RunStatus::halted) {
    result.status = status;
    locate(result.error, current_program_, current_line_);
    result.error = Diagnostic{};
    if (status == RunStatus::halted) stack_.clear();  // HALT cannot be resumed
  }
  if (result.status == RunStatus::error || result.status == RunStatus::interrupted || result.status == RunStatus::collision)
    memory_.last_error = error_code(result.error.message);  // what ERROR() returns from now on
  for (const auto& t : tasks_) {  // STATUS lists them (dialect §7b)
    TaskReport report{t->number, t->program, t->aborted ? "aborted" : "completed"};
    const Program* at = t.get() == running_ ? current_program_ : t->at_program;
    const int line = t.get() == running_ ? current_line_ : t->at_line;
    if (!t->done && at) report.state = fmt::format("stopped at step {} of {}", line - at->line, at->name);
    else if (!t->done) report.state = "not started";
    result.tasks.push_back(std::move(report));
  }
  if (!tasks_.empty()) stack_.clear();  // with tasks the run cannot be resumed
  if (result.status == RunStatus::completed) {
    result.program = name;
    result.line = result.step = 0;
  } else if (!stack_.empty() || (tasks_.empty() && result.status == RunStatus::collision) || halt_) {
    stopped_ = Stopped{stack_.take(), result.status, name, speed_always_, speed_next_, last_motion_,
                       duration_always_, duration_next_, halt_.has_value(), pin_programs()};
  }
  result.interrupt = halt_;
  result.reaction_stops = std::move(reaction_stops_);
  reaction_stops_.clear();
  result.motion_times = std::move(motion_times_);
  result.motion_times_omitted = motion_times_omitted_;
  motion_times_.clear();
  stack_.clear();
  result.warnings = std::move(warnings_);
  warnings_.clear();
  for (const auto& [program, line] : motion_sites_) {
    Diagnostic at;
    locate_at(at, *program, line);
    at.source_line.erase(0, at.source_line.find_first_not_of(" \t"));
    result.motions.push_back({at.step, at.program, line, std::move(at.source_line)});
  }
  return result;
}

// --- statements -----------------------------------------------------------------------------

// The dispatch loop. The statements that dominate loops (real assignments, jumps, FOR steps)
// run inline here through their compiled expressions; any value the compiled form does not
// handle, and every other statement, goes through execute(), which raises the exact errors.
RunStatus Evaluator::loop() {
  const std::atomic<bool>* interrupt = limits_.interrupt;
  const std::uint64_t max_statements = limits_.max_statements;
  const bool hooked = static_cast<bool>(step_hook_);  // the debugger's, tested once per instruction
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
      if (!reactions().empty()) {
        bool pushed = false;
        if (const RunStatus s = react(pushed); s != RunStatus::completed) return s;
        if (pushed) break;
      }
      const Instr& in = code[f.pc];
      current_line_ = in.line;
      // Ctrl-C: stop before this step, which PROCEED and RETRY then run.
      if (interrupt && interrupt->load(std::memory_order_relaxed)) return stop(fault(Message::interrupted));
      if (hooked) [[unlikely]]
        if (const RunStatus s = at_step(in, f); s != RunStatus::completed) return s;
      ++f.pc;
      if (++statements_ > budget_) {  // this execution's steps (a run or a resumption)
        if (budget_ >= max_statements)
          return stop(fault(Message::too_many_statements, fmt::format("more than {}", max_statements)));
        --f.pc;  // the task's time slice is used up: the step runs when it comes back
        --statements_;
        block_until(now_ + kSliceS);
        return RunStatus::completed;
      }
      double x;
      switch (in.code) {
        case Code::assign:
          if (in.real_target && in.fast0 && run_root(in.fast0, x)) {
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
          if (in.fast0 && run_root(in.fast0, x)) {
            if (x == 0) f.pc = in.jump;
            continue;
          }
          break;
        case Code::jump_true:
          if (in.fast0 && run_root(in.fast0, x)) {
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
      if (running_) {  // tasks (dialect §7b)
        // The robot task's statement carried the arm (or the hand) ahead in time: the other
        // tasks run meanwhile, it goes on at that time.
        if (!yield_ && robot_task() && sim_.time_s() > now_) block_until(sim_.time_s());
        if (yield_) return RunStatus::completed;
      }
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
      return motion(in);
    case Code::hand: return hand(in);
    case Code::wait: case Code::wait_event: return wait(in);
    case Code::break_: return finish_motion();
    case Code::pause: case Code::halt:  // PAUSE and HALT wait for the motion
      if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
      return in.code == Code::halt ? RunStatus::halted : RunStatus::paused;
    default:
      statement(in);
      return RunStatus::completed;
  }
}

RunStatus Evaluator::hand(const Instr& in) {
  using motion::HandState;
  const ast::Kw w = in.word;
  const HandState h = w == ast::Kw::open || w == ast::Kw::openi     ? HandState::open
                      : w == ast::Kw::close || w == ast::Kw::closei ? HandState::closed
                                                                    : HandState::relaxed;
  require_robot();
  if (w == ast::Kw::open || w == ast::Kw::close || w == ast::Kw::relax) {
    sim_.request_hand(h);
    return RunStatus::completed;
  }
  // The hand acts where the motion ended, then HAND.TIME.
  if (const RunStatus s = check_motion(sim_.finish_motion()); s != RunStatus::completed) return s;
  hand_changed(h, in.line);
  return check_dwell(sim_.hand_immediate(h, memory_.settings.hand_time_s, step_of(in.line)), in.line);  // OPENI ...
}

void Evaluator::statement(const Instr& in) {
  Frame& f = stack_.back();
  switch (in.code) {
    case Code::assign: {
      if (double x; in.args[0].plain && in.target.text[0] != '$' && in.target.text[0] != '#'
                    && (run_fast(in.args[0], x) || try_real(in.args[0], x)))
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
    case Code::type: return type(in);
#define ASIMOV_MOTION(kw, ...) case Code::kw:
#include "instructions.def"
    case Code::hand: case Code::wait: case Code::wait_event: case Code::break_: case Code::pause: case Code::halt:
      return;  // execute()
    case Code::signal:  // SIGNAL n, ...: n > 0 on, n < 0 off, 0 ignored
      for (const Node& n : in.args) {
        set_signal(signal_number(n, true));
      }
      return;
    case Code::accel: {  // ACCEL (profile) a, d: an omitted one is kept; out of [1, 100]: the nearer end
      if (in.args[0].kind != NodeKind::absent) to_real(eval(in.args[0]), "ACCEL profile");  // profile 0 is used
      double* ramp[2] = {&memory_.settings.accel, &memory_.settings.decel};
      for (std::size_t k = 1; k < in.args.size(); ++k)
        if (in.args[k].kind != NodeKind::absent)
          *ramp[k - 1] = std::clamp(to_real(eval(in.args[k]), k == 1 ? "ACCEL acceleration" : "ACCEL deceleration"), 1.0, 100.0);
      return;
    }
    case Code::timer: {
      const int k = to_index(to_real(eval(in.args[0]), "timer number"));
      if (k < 1 || k > 16) raise(Message::illegal_value, fmt::format("timer {}", k));
      memory_.timers[static_cast<std::size_t>(k)] = {to_real(eval(in.args[1]), "TIMER value"), sim_.time_s()};
      return;
    }
    case Code::unsupported:
      if (!in.always) raise(Message::not_supported, in.target.text);
      return warn_once(in.target.text, in);
    case Code::io: return io(in);
    case Code::execute: return execute_task(in);
    case Code::task: return task_instruction(in);
    case Code::robot: return robot_attach(in.always);
    case Code::react: case Code::reacte: case Code::ignore: case Code::lock: return reaction_instruction(in);
    case Code::prompt: return prompt(in);
    case Code::duration: {
      const double t = to_real(eval(in.args[0]), "DURATION");
      if (!(t >= 0)) raise(Message::illegal_value, fmt::format("DURATION {}", format_number(t)));
      if (in.always) duration_always_ = t, duration_next_.reset();
      else duration_next_ = t;
      return;
    }
    case Code::enable: case Code::disable: case Code::parameter: return settings(in);
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
    case Code::tool: {
      require_robot();
      if (in.args.empty()) sim_.settings().tool = motion::Location::Identity();  // TOOL = TOOL NULL
      else sim_.settings().tool = as_transformation(eval(in.args[0]));
      return;
    }
    case Code::base: {
      require_robot();
      if (in.args.size() == 1 && in.args[0].kind != NodeKind::absent) {
        const Value v = eval(in.args[0]);
        if (kind_of(v) != Kind::real) {
          sim_.settings().base = as_transformation(v);
          return;
        }
      }
      double x[4] = {0, 0, 0, 0};  // BASE dx, dy, dz, rz (omitted: 0)
      for (std::size_t k = 0; k < in.args.size(); ++k)
        if (in.args[k].kind != NodeKind::absent) x[k] = to_real(eval(in.args[k]), "BASE");
      sim_.settings().base = motion::trans(x[0], x[1], x[2], x[3], 0, 0);
      return;
    }
    case Code::configure: {
      // A word without meaning for this arm (a SCARA's ABOVE, any word on a numeric-IK arm):
      // ignored as before, said once (docs/robots.md).
      const ast::Kw w = in.word;
      const auto word = w == ast::Kw::righty || w == ast::Kw::lefty ? robots::ConfigurationWord::arm
                        : w == ast::Kw::above || w == ast::Kw::below ? robots::ConfigurationWord::elbow
                                                                     : robots::ConfigurationWord::wrist;
      const char* name = w == ast::Kw::righty ? "RIGHTY" : w == ast::Kw::lefty ? "LEFTY" : w == ast::Kw::above ? "ABOVE"
                         : w == ast::Kw::below ? "BELOW" : w == ast::Kw::flip ? "FLIP" : w == ast::Kw::noflip ? "NOFLIP" : nullptr;
      if (name && !robots::configuration_word_applies(sim_.robot(), word))
        warn_once(std::string(name) + " (no meaning for this arm: ignored)", in);
      return request_configuration(in.word, sim_.settings().request);
    }
    case Code::speed: {
      const double s = to_real(eval(in.args[0]));
      if (!(s > 0 && s <= 100)) raise(Message::illegal_value, fmt::format("SPEED {}", format_number(s)));
      if (in.monitor) {
        speed_monitor_ = s;
      } else if (in.always) {
        speed_always_ = s;
        speed_next_.reset();
      } else {
        speed_next_ = s;
      }
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
    if (double x; given && run_fast(in.args[i], x)) owned.scalar.emplace(x);
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
  if (f.restore_priority >= 0) reactions().set_priority(f.restore_priority);  // a reaction's RETURN
  if (f.trap) reactions().trapping = false;
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

RunStatus Evaluator::finish_motion() {
  if (!sim_.motion_pending()) return RunStatus::completed;
  const RunStatus s = check_motion(sim_.finish_motion());
  moving_until_ = sim_.time_s();  // for the other tasks the arm moves until then (STATE(2))
  return s;
}

// The motion that the simulator finished failed: contact stops the run, an error is reported
// at the motion instruction.
RunStatus Evaluator::check_motion(const motion::MotionResult& r) {
  switch (r.status) {
    case motion::MotionStatus::ok: return RunStatus::completed;
    case motion::MotionStatus::collision: contact_ = r.collision; return RunStatus::collision;
    case motion::MotionStatus::interrupted:
      if (r.interrupt.by_condition) {  // a REACTI: the step waiting for the motion runs again later
        braked(r.interrupt);
        throw Braked{};
      }
      // Ctrl-C halted the motion: reported at the motion instruction, as a contact is; the step
      // that was waiting for the motion (none at the run's end) runs again after its rest.
      halt_ = r.interrupt;
      if (!stack_.empty()) --stack_.back().pc;
      current_program_ = motion_program_;
      current_line_ = motion_line_;
      return stop(fault(Message::interrupted));
    case motion::MotionStatus::error:
      current_program_ = motion_program_;  // reported at the motion instruction
      current_line_ = motion_line_;
      return stop(Fault{Message::motion, r.error.message, r.error.detail});
  }
  return RunStatus::completed;
}

RunStatus Evaluator::check_dwell(const motion::MotionResult& r, int line) {
  if (r.status == motion::MotionStatus::interrupted && r.interrupt.waiting) {
    // Ctrl-C in a wait with parts moving (WAIT.EVENT, a dwell): no motion halted, nothing to
    // resume; reported at the statement that waited, which runs again on PROCEED.
    if (!stack_.empty()) --stack_.back().pc;
    return stop(fault(Message::interrupted));
  }
  if (r.status == motion::MotionStatus::collision) {  // located at the statement that waited
    motion_program_ = current_program_;
    motion_line_ = line;
  }
  return check_motion(r);
}

RunStatus Evaluator::motion(const Instr& in) {
  require_robot();
  // Without continuous path a motion instruction waits for the previous motion to end; with it
  // the simulator blends the two (docs/blending.md), and relative motions start from where the
  // pending motion ends (planned_here / planned_joints: HERE and the joints once it has).
  if (!sim_.settings().continuous_path)
    if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
  const bool straight = straight_path(in.code);
  std::optional<Value> target;
  switch (in.code) {
    case Code::ready: target = motion::ready_target(sim_.robot()); break;  // the robot's READY
    case Code::align: target = motion::align_target(sim_.planned_here()); break;
    case Code::drive: {  // DRIVE j, change, speed: one joint, relative, at speed % of its maximum
      const int j = to_index(to_real(eval(in.args[0]), "joint"));
      const double change = to_real(eval(in.args[1]), "DRIVE change");
      const double s = to_real(eval(in.args[2]), "DRIVE speed");
      if (!(s >= 1 && s <= 100)) raise(Message::illegal_value, fmt::format("DRIVE speed {}", format_number(s)));
      robots::JointVector target;
      if (!motion::drive_target(sim_.planned_joints(), j, change, target))
        raise(Message::illegal_value, fmt::format("joint {}", j));
      MotionRequest m;
      m.joints = target;
      m.speed = motion::drive_speed(speed_monitor_, s);
      m.program = current_program_;
      m.line = in.line;
      return start_motion(m);  // the program speed does not apply and is not consumed
    }
    case Code::draw: {  // SHIFT(HERE BY dx, dy, dz), HERE after the previous motion; omitted = 0
      double d[3] = {0, 0, 0};
      for (std::size_t k = 0; k < in.args.size() && k < 3; ++k)
        if (in.args[k].kind != NodeKind::absent) d[k] = to_real(eval(in.args[k]), "DRAW");
      target = motion::draw_target(sim_.planned_here(), d[0], d[1], d[2]);
      break;
    }
    case Code::move: case Code::moves: target = eval(in.args[0]); break;
    case Code::movet: case Code::movest: {  // the hand opens (h != 0) or closes when it starts
      target = eval(in.args[0]);
      sim_.request_hand(motion::movet_hand(to_real(eval(in.args[1]), "MOVET hand")));
      break;
    }
    case Code::appro: case Code::appros: {
      const Value loc = eval(in.args[0]);
      const double d = to_real(eval(in.args[1]), "APPRO distance");
      target = motion::appro_target(as_pose(loc, sim_), d);
      break;
    }
    case Code::depart: case Code::departs: {  // from where the previous motion ends
      const double d = to_real(eval(in.args[0]), "DEPART distance");
      target = motion::depart_target(sim_.planned_here(), d);
      break;
    }
    default: raise(Message::not_supported, "a motion without a target in Evaluator::motion");
  }
  MotionRequest m;
  m.speed = {speed_monitor_, speed_next_.value_or(speed_always_), -1, duration_next_.value_or(duration_always_)};
  m.straight = straight;
  m.program = current_program_;
  m.line = in.line;
  if (const auto* j = std::get_if<robots::JointVector>(&*target); j && !straight) {
    m.joints = *j;
  } else {
    if (kind_of(*target) != Kind::trans && kind_of(*target) != Kind::ppoint)
      raise(Message::illegal_value, fmt::format("location expected, not a {}", kind_name(kind_of(*target))));
    m.pose = as_pose(*target, sim_);
  }
  // Consumed once started: a REACTI stopping the motion before (Braked) runs this step again.
  const RunStatus s = start_motion(m);
  speed_next_.reset();
  duration_next_.reset();
  return s;
}

// PROCEED / RETRY after Ctrl-C halted a motion: the rest of it, from where the arm stopped;
// when a DO has moved the arm since (the simulator dropped the rest), the same motion
// instruction again from where the arm is. The monitor speed now in effect applies.
RunStatus Evaluator::resume_halted_motion() {
  if (!last_motion_) return RunStatus::completed;
  motion_program_ = last_motion_->program;
  motion_line_ = last_motion_->line;
  if (sim_.halted_motion()) return check_motion(sim_.resume_motion(speed_monitor_));
  MotionRequest m = *last_motion_;
  m.speed.monitor = speed_monitor_;
  return start_motion(m);
}

// Starts a resolved motion (also RETRY's restart of an interrupted one).
RunStatus Evaluator::start_motion(const MotionRequest& m) {
  const int step = m.line - m.program->line;
  if (std::find(motion_sites_.begin(), motion_sites_.end(), std::pair{m.program, m.line}) == motion_sites_.end())
    motion_sites_.emplace_back(m.program, m.line);
  // OPEN / CLOSE act as this motion starts: the grasp or release where the previous motion
  // ended (a stop, also with continuous path), before this one is planned (a carried part
  // widens its step bounds).
  const std::optional<motion::HandState> hand_request = sim_.hand().pending;
  if (hand_request && sim_.cell_runtime()) {
    if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
    hand_changed(*hand_request, m.line);
  }
  robots::JointVector earlier = sim_.planned_joints();  // where this motion starts from
  motion::SpeedSettings speed = m.speed;
  speed.accel = memory_.settings.accel;  // ACCEL in effect now
  speed.decel = memory_.settings.decel;
  const motion::MotionResult r = m.joints ? sim_.start_joint_move(*m.joints, speed, step)
                                          : sim_.start_move(m.pose, m.straight, speed, step);
  // A halt or contact here is the previous motion's (carried out up to where this one starts).
  if (r.status == motion::MotionStatus::interrupted || r.status == motion::MotionStatus::collision)
    return check_motion(r);
  motion_program_ = m.program;
  motion_line_ = m.line;
  last_motion_ = m;
  if (r.status == motion::MotionStatus::error)  // reported at the statement that started it
    return stop(Fault{Message::motion, r.error.message, r.error.detail});
  if (const auto timing = sim_.pending_timing()) {
    record_timing(*timing, m.program->name);
    earlier_destination_ = std::move(earlier);
    earlier_until_ = timing->start_s;
  }
  return RunStatus::completed;
}

void Evaluator::record_timing(const motion::MotionTiming& t, const std::string& program) {
  if (motion_times_.size() >= kMaxMotionTimes) {
    ++motion_times_omitted_;
    return;
  }
  motion_times_.push_back({t.step, program, t.start_s, t.duration_s, t.blended});
}

void Evaluator::type(const Instr& in) {
  bool newline = true;
  const std::string text = format_items(in.formats, eval_all(in.args), newline);
  out_ << text;
  if (newline) out_ << '\n';
}

std::vector<Value> Evaluator::eval_all(const std::vector<Node>& nodes) {
  std::vector<Value> values;
  values.reserve(nodes.size());
  for (const Node& n : nodes) values.push_back(eval(n));
  return values;
}

motion::Location Evaluator::as_transformation(const Value& v) {
  if (const auto* t = std::get_if<motion::Location>(&v)) return *t;
  raise(Message::illegal_value, fmt::format("transformation expected, not a {}", kind_name(kind_of(v))));
}

// --- waiting, terminal input, settings -------------------------------------------------------

// WAIT cond: the clock advances tick by tick until cond holds (bare WAIT: one tick).
// WAIT.EVENT , t: t seconds. Both wait for the motion first.
RunStatus Evaluator::wait(const Instr& in) {
  if (running_) return task_wait(in);
  if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
  if (in.code == Code::wait_event) {
    const double t = to_real(eval(in.args[1]), "WAIT.EVENT time");
    if (!(t >= 0)) raise(Message::illegal_value, fmt::format("WAIT.EVENT {}", format_number(t)));
    return check_dwell(sim_.wait(t, step_of(in.line)), in.line);
  }
  if (in.args.empty()) {
    // One tick. Bare WAITs one after another with no time passing in between (a polling loop
    // `10 IF NOT SIG(1001) THEN` / `WAIT` / `GOTO 10`) are one wait: past Limits::max_wait_s it
    // stops as WAIT condition does, with the same hint (dialect §6).
    const double now = sim_.time_s();
    if (now != bare_wait_end_) bare_wait_start_ = now;
    if (now - bare_wait_start_ >= limits_.max_wait_s)
      return stop(fault(Message::wait_limit, fmt::format("a loop of WAIT still waiting after {} s{}",
                                                         format_number(limits_.max_wait_s), undriven_signals())));
    const RunStatus s = check_dwell(sim_.wait(limits_.tick_s, step_of(in.line)), in.line);
    bare_wait_end_ = sim_.time_s();
    return s;
  }
  const double give_up = sim_.time_s() + limits_.max_wait_s;
  waited_.clear();
  while (to_real(eval(in.args[0]), "WAIT condition") == 0) {
    if (limits_.interrupt && limits_.interrupt->load(std::memory_order_relaxed)) {
      --stack_.back().pc;  // as between steps: PROCEED waits again
      return stop(fault(Message::interrupted));
    }
    if (sim_.time_s() >= give_up)
      return stop(fault(Message::wait_limit,
                        fmt::format("still false after {} s{}", format_number(limits_.max_wait_s), undriven_signals())));
    if (const RunStatus s = check_dwell(sim_.wait(limits_.tick_s, step_of(in.line)), in.line); s != RunStatus::completed)
      return s;
    if (!reactions().empty()) {  // a reaction due interrupts the wait, which goes on after it
      reactions().see([this](int k) { return signal_state(k); });
      if (reactions().due()) {
        --stack_.back().pc;
        return RunStatus::completed;
      }
    }
  }
  return RunStatus::completed;
}

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

// PARAMETER name = value, ENABLE / DISABLE switch, ...
void Evaluator::settings(const Instr& in) {
  if (in.code == Code::parameter)
    return set_parameter(in.target.text, to_real(eval(in.args[0]), "PARAMETER value"), memory_.settings, sim_);
  for (const Node& n : in.args)
    if (!set_switch(n.text, in.code == Code::enable, memory_.settings, sim_))
      warn_once((in.code == Code::enable ? "ENABLE " : "DISABLE ") + n.text, in);
}

// --- tasks (dialect §7b) --------------------------------------------------------------------

// Runs stack_ (task 0) and, once EXECUTE has started others, every task by cooperative
// scheduling on the simulated clock: a task runs until it gives way (WAIT, WAIT.EVENT, RELEASE,
// CYCLE.END, the robot task when its statement carried the arm ahead in time, or the end of
// its time slice), then the task that may run earliest goes on; at equal times the next one by
// number after the task that ran. The clock advances only when no task can run now.
RunStatus Evaluator::run_tasks() {
  for (;;) {
    yield_ = false;
    if (const RunStatus s = loop(); s != RunStatus::completed) return s;
    if (!running_) return RunStatus::completed;  // task 0 alone, as without tasks
    Task& ran = *running_;
    ran.done = !yield_;
    ran.at_program = current_program_;
    ran.at_line = current_line_;
    std::swap(stack_, ran.stack);
    Task* next = next_task();
    if (!next) return RunStatus::completed;
    try {
      if (const RunStatus s = advance_clock(next->wake_s); s != RunStatus::completed) return s;
    } catch (const Braked&) {  // a REACTI stopped the robot task's motion: it goes on from now
      for (const auto& t : tasks_)
        if (t->number == robot_task_) t->wake_s = std::min(t->wake_s, now_);
    }
    switch_to(next);
  }
}

Evaluator::Task* Evaluator::next_task() const {
  Task* best = nullptr;
  const std::size_t n = tasks_.size();
  std::size_t start = 0;  // round robin: from the task after the one that ran
  for (std::size_t i = 0; i < n; ++i)
    if (tasks_[i].get() == running_) start = i + 1;
  for (std::size_t k = 0; k < n; ++k) {
    Task* t = tasks_[(start + k) % n].get();
    if (!t->done && (!best || t->wake_s < best->wake_s)) best = t;
  }
  return best;
}

// The clock moves to `t`; an idle arm's clock follows it (a pending motion is carried out first).
RunStatus Evaluator::advance_clock(double t) {
  if (t <= now_) return RunStatus::completed;
  now_ = t;
  if (sim_.time_s() >= now_) return RunStatus::completed;
  if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
  if (sim_.time_s() < now_) return check_motion(sim_.wait(now_ - sim_.time_s()));
  return RunStatus::completed;
}

void Evaluator::switch_to(Task* t) {
  running_ = t;
  std::swap(stack_, t->stack);
  ctx_.globals = t->globals.data();
  budget_ = std::min(limits_.max_statements, statements_ + kSliceStatements);
}

void Evaluator::block_until(double t) {
  running_->wake_s = t;
  yield_ = true;
}

void Evaluator::require_robot() const {
  if (task_number() != robot_task_)
    raise_text("*Robot not attached to this program*", fmt::format("task {}", task_number()));
}

// Robot ATTACH () / DETACH () (dialect §7b): DETACH () gives the robot away; ATTACH () takes it
// when no other running task holds it.
void Evaluator::robot_attach(bool attach) {
  const int n = task_number();
  if (!attach) {
    if (robot_task_ == n) robot_task_ = -1;
    return;
  }
  bool owner_running = tasks_.empty() && robot_task_ == 0 && n != 0;
  for (const auto& t : tasks_) owner_running = owner_running || (t->number == robot_task_ && !t->done);
  if (robot_task_ != n && robot_task_ >= 0 && owner_running)
    raise(Message::illegal_value, fmt::format("the robot is attached to task {}", robot_task_));
  robot_task_ = n;
}

// WAIT, WAIT.EVENT with tasks: the task gives way to the others until its time or condition.
// The robot task first lets its motion end (the step runs again at the motion's end).
RunStatus Evaluator::task_wait(const Instr& in) {
  if (robot_task()) {
    if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
    if (sim_.time_s() > now_) {
      --stack_.back().pc;
      block_until(sim_.time_s());
      return RunStatus::completed;
    }
  }
  Task& t = *running_;
  if (in.code == Code::wait_event) {
    const double s = to_real(eval(in.args[1]), "WAIT.EVENT time");
    if (!(s >= 0)) raise(Message::illegal_value, fmt::format("WAIT.EVENT {}", format_number(s)));
    block_until(now_ + s);
    return RunStatus::completed;
  }
  if (in.args.empty()) {
    block_until(now_ + limits_.tick_s);
    return RunStatus::completed;
  }
  if (t.wait_since < 0) waited_.clear();
  if (to_real(eval(in.args[0]), "WAIT condition") != 0) {
    t.wait_since = -1;
    return RunStatus::completed;
  }
  if (t.wait_since < 0) t.wait_since = now_;
  if (now_ - t.wait_since >= limits_.max_wait_s) {
    t.wait_since = -1;
    return stop(fault(Message::wait_limit,
                      fmt::format("still false after {} s{}", format_number(limits_.max_wait_s), undriven_signals())));
  }
  --stack_.back().pc;  // the condition is tested again when the task comes back
  block_until(now_ + limits_.tick_s);
  return RunStatus::completed;
}

// EXECUTE [n] prog(args): task n runs prog from now on; this task goes on. Arguments go by value.
void Evaluator::execute_task(const Instr& in) {
  const int n = in.args[0].kind == NodeKind::absent ? 0 : to_index(to_real(eval(in.args[0]), "task number"));
  if (n < 0 || n > kMaxTask) raise(Message::illegal_value, fmt::format("task {}", n));
  const auto& program = memory_.programs[static_cast<std::size_t>(in.program)];
  if (!program) raise(Message::undefined_name, in.target.text);
  if (!program->executable) raise(Message::not_executable, program->name);
  if (in.args.size() - 1 > program->params.size())
    raise(Message::illegal_value, fmt::format("{} takes {} arguments", program->name, program->params.size()));
  if (!running_) {  // the first EXECUTE: the running execution becomes task 0
    auto first = std::make_unique<Task>();
    first->program = run_program_;
    first->globals = globals_;
    first->reactions = std::move(reactions0_);
    reactions0_ = Reactions{};
    running_ = first.get();
    tasks_.push_back(std::move(first));
    now_ = sim_.time_s();
  }
  for (auto it = tasks_.begin(); it != tasks_.end(); ++it) {
    if ((*it)->number != n) continue;
    if (!(*it)->done) raise(Message::illegal_value, fmt::format("task {} is executing", n));
    tasks_.erase(it);  // a task that ended starts again
    break;
  }
  auto t = std::make_unique<Task>();
  t->number = n;
  t->program = program->name;
  t->wake_s = now_;
  Frame& top = t->stack.next();
  top.program = program.get();
  top.owned.clear();
  top.owned.resize(program->params.size() + program->autos.size());
  for (std::size_t i = 1; i < in.args.size(); ++i)
    if (in.args[i].kind != NodeKind::absent) top.owned[i - 1].scalar = eval(in.args[i]);
  for (Variable& v : top.owned) top.params.push_back(&v);
  top.temps.resize(static_cast<std::size_t>(program->temps));
  t->stack.commit();
  t->globals = globals_;
  for (std::size_t slot = 0; slot < memory_.symbols.globals.size(); ++slot)  // its own LOCAL variables
    if (memory_.symbols.globals[slot].find('@') != std::string::npos) t->globals[slot] = &t->locals.emplace_back();
  auto at = std::find_if(tasks_.begin(), tasks_.end(), [&](const auto& other) { return other->number > n; });
  tasks_.insert(at, std::move(t));
  budget_ = std::min(limits_.max_statements, statements_ + kSliceStatements);
}

// ABORT n / KILL n end task n (its next step does not run); CYCLE.END n waits for its end;
// RELEASE gives way to the other tasks.
void Evaluator::task_instruction(const Instr& in) {
  const int n = in.args.empty() ? -1 : to_index(to_real(eval(in.args[0]), "task number"));
  Task* task = nullptr;
  for (const auto& t : tasks_)
    if (t->number == n) task = t.get();
  switch (in.io) {
    case IoOp::abort:
    case IoOp::kill:
      if (n == task_number()) {
        if (running_) running_->aborted = true;
        return stack_.clear();
      }
      if (task) {
        task->done = task->aborted = true;
        task->stack.clear();
      }
      return;
    case IoOp::cycle_end:
      if (!task || task->done || task == running_) return;
      --stack_.back().pc;
      return block_until(now_ + limits_.tick_s);
    case IoOp::release:
      if (running_) block_until(now_);
      return;
    default: return;
  }
}

// --- files (dialect §7a) --------------------------------------------------------------------

int Evaluator::unit_number(const Instr& in) {
  const int lun = to_index(to_real(eval(in.args[0]), "logical unit"));
  if (lun < 0 || lun > FileUnits::kLastUnit) raise(Message::illegal_value, fmt::format("logical unit {}", lun));
  return lun;
}

// ATTACH / DETACH / FOPENR ... / READ / WRITE on a disk unit. As on V+, what the program is
// expected to handle (end of file, a missing file) only sets IOSTAT; a path leaving the folder,
// a unit used wrongly and a device that is not simulated stop the program.
void Evaluator::io(const Instr& in) {
  const std::size_t first_item = static_cast<std::size_t>(in.temp);
  auto text_item = [&]() -> std::string {
    return first_item < in.args.size() ? to_string_value(eval(in.args[first_item])) : std::string();
  };
  std::string error;
  auto check = [&] {
    if (!error.empty()) raise(Message::illegal_value, fmt::format("{}: {}", in.target.text, error));
  };
  if (in.io == IoOp::attach) {
    std::string device;
    for (char c : text_item()) device += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (!device.empty() && device != "DISK" && device != "NFS") {
      bool network = false;
      for (std::string_view d : kNetworkDevices) network = network || device.rfind(d, 0) == 0;
      raise(Message::not_supported, fmt::format("ATTACH \"{}\"{}", device, network ? "; " + std::string(kNetworkHint) : ""));
    }
    const double mode = in.args.size() > 1 && first_item > 1 && in.args[1].kind != NodeKind::absent
        ? to_real(eval(in.args[1]), "ATTACH mode") : 0;
    int lun = 0;
    if (static_cast<int>(mode) & 4) {  // allocate the next free unit, returned in the variable
      if (in.args[0].kind != NodeKind::variable) raise(Message::illegal_value, "ATTACH mode 4 needs a variable for the unit");
      lun = files_.free_unit();
      if (lun < 0) raise(Message::illegal_value, "ATTACH: no logical unit left");
      store(in.args[0], static_cast<double>(lun));
    } else {
      lun = unit_number(in);
    }
    if (!files_.attach(lun)) raise(Message::illegal_value, fmt::format("ATTACH: logical unit {} is attached already", lun));
    files_.set_iostat(lun, kIoOk);
    return;
  }
  const int lun = unit_number(in);
  switch (in.io) {
    case IoOp::detach:
      if (!files_.detach(lun, error) && error.empty()) error = fmt::format("logical unit {} is not attached", lun);
      return check();
    case IoOp::fopenr: case IoOp::fopenw: case IoOp::fopena: case IoOp::fopend: {
      const FileUnits::Open mode = in.io == IoOp::fopenr ? FileUnits::Open::read
                                 : in.io == IoOp::fopenw ? FileUnits::Open::write
                                 : in.io == IoOp::fopena ? FileUnits::Open::append : FileUnits::Open::directory;
      files_.open(lun, mode, text_item(), error);
      return check();
    }
    case IoOp::fclose: files_.close(lun, error); return check();
    case IoOp::fempty: files_.empty(lun, text_item(), error); return check();
    case IoOp::fdelete: files_.remove(lun, text_item(), error); return check();
    case IoOp::read: {
      if (in.args.size() > 1 && first_item > 1 && in.args[1].kind != NodeKind::absent
          && to_real(eval(in.args[1]), "record number") != 0)
        raise(Message::not_supported, "READ of a numbered record");
      const auto record = files_.read_record(lun, error);
      check();
      if (!record) return;  // end of file: IOSTAT says so, the variables are unchanged
      const std::size_t count = in.args.size() - first_item;
      if (count == 1 && in.args[first_item].text[0] == '$') {  // the whole record
        if (record->size() > kMaxStringLength) raise(Message::illegal_value, "READ: record longer than 128 characters");
        return store(in.args[first_item], *record);
      }
      // Several variables (or a real): the record's fields, separated by blanks, tabs or commas.
      std::vector<std::string> fields;
      std::string field;
      for (char c : *record + ' ') {
        if (c == ' ' || c == '\t' || c == ',') {
          if (!field.empty()) fields.push_back(field);
          field.clear();
        } else {
          field += c;
        }
      }
      for (std::size_t k = 0; k < count; ++k) {
        const Node& target = in.args[first_item + k];
        if (k >= fields.size())
          raise(Message::illegal_value, fmt::format("READ: the record has {} fields for {} variables", fields.size(), count));
        if (target.text[0] == '$') {
          store(target, fields[k]);
          continue;
        }
        const auto v = parse_reply_number(fields[k]);
        if (!v) raise(Message::illegal_value, fmt::format("READ: \"{}\" is not a number", fields[k]));
        store(target, *v);
      }
      return;
    }
    case IoOp::write: {
      bool record_end = true;
      std::vector<Value> values;
      for (std::size_t k = first_item; k < in.args.size(); ++k) values.push_back(eval(in.args[k]));
      std::string text = format_items(in.formats, values, record_end);
      if (record_end) text += "\r\n";  // V+ records end with CR LF; /S leaves the record open
      files_.write(lun, text, error);
      return check();
    }
    case IoOp::attach:  // handled above
    case IoOp::abort: case IoOp::kill: case IoOp::cycle_end: case IoOp::release:  // task_instruction
      break;
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
