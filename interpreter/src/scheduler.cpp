// Stage 3, the task scheduler (scheduler.hpp, dialect §7b): tasks, their clock, WAIT.
#include "scheduler.hpp"

#include "arm_controller.hpp"
#include "evaluator.hpp"
#include "operators.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace asimov::interpreter {

void Scheduler::begin_execution() {
  bare_wait_end_ = -1;
  reactions0_ = Reactions{};  // reactions, priority and trap are the execution's (dialect §7c)
}

void Scheduler::begin_run() {
  reaction_stops_.clear();
  brake_signal_ = 0;
  budget_ = {0, limits_.max_statements};
  robot_task_ = 0;
}

void Scheduler::end_run(RunResult& result, const Program* program, int line) {
  for (const auto& t : tasks_) {  // STATUS lists them (dialect §7b)
    TaskReport report{t->number, t->program, t->aborted ? "aborted" : "completed"};
    const Program* at = t.get() == running_ ? program : t->at_program;
    const int at_line = t.get() == running_ ? line : t->at_line;
    if (!t->done && at) report.state = fmt::format("stopped at step {} of {}", at_line - at->line, at->name);
    else if (!t->done) report.state = "not started";
    result.tasks.push_back(std::move(report));
  }
  result.reaction_stops = std::move(reaction_stops_);
  reaction_stops_.clear();
}

void Scheduler::drop_tasks() {
  tasks_.clear();
  running_ = nullptr;
}

// Runs the VM's stack (task 0) and, once EXECUTE has started others, every task by cooperative
// scheduling on the simulated clock: a task runs until it gives way (WAIT, WAIT.EVENT, RELEASE,
// CYCLE.END, the robot task when its statement carried the arm ahead in time, or the end of
// its time slice), then the task that may run earliest goes on; at equal times the next one by
// number after the task that ran. The clock advances only when no task can run now.
RunStatus Scheduler::run_tasks() {
  for (;;) {
    yield_ = false;
    if (const RunStatus s = vm_.loop(); s != RunStatus::completed) return s;
    if (!running_) return RunStatus::completed;  // task 0 alone, as without tasks
    Task& ran = *running_;
    ran.done = !yield_;
    ran.at_program = vm_.current_program();
    ran.at_line = vm_.current_line();
    std::swap(vm_.stack(), ran.stack);
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

Task* Scheduler::next_task() const {
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
RunStatus Scheduler::advance_clock(double t) {
  if (t <= now_) return RunStatus::completed;
  now_ = t;
  if (sim_.time_s() >= now_) return RunStatus::completed;
  if (const RunStatus s = arm_.finish_motion(); s != RunStatus::completed) return s;
  if (sim_.time_s() < now_) return arm_.check_motion(sim_.wait(now_ - sim_.time_s()));
  return RunStatus::completed;
}

void Scheduler::switch_to(Task* t) {
  running_ = t;
  std::swap(vm_.stack(), t->stack);
  vm_.fast_ctx().globals = t->globals.data();
  budget_.until = std::min(limits_.max_statements, budget_.done + kSliceStatements);
}

void Scheduler::block_until(double t) {
  running_->wake_s = t;
  yield_ = true;
}

bool Scheduler::gives_way() {
  // The robot task's statement carried the arm (or the hand) ahead in time: the other tasks
  // run meanwhile, it goes on at that time.
  if (!yield_ && robot_task() && sim_.time_s() > now_) block_until(sim_.time_s());
  return yield_;
}

void Scheduler::require_robot() const {
  if (task_number() != robot_task_)
    raise_text("*Robot not attached to this program*", fmt::format("task {}", task_number()));
}

double Scheduler::task_state(int number) const {
  if (tasks_.empty()) return number == 0 ? 4.0 : 0.0;  // task 0 alone
  for (const auto& t : tasks_)
    if (t->number == number) return t->done ? 0.0 : 4.0;
  return 0.0;
}

bool Scheduler::executing(const std::string& program, const std::string& run_program) const {
  bool executing = tasks_.empty() && run_program == program;
  for (const auto& t : tasks_) executing = executing || (!t->done && t->program == program);
  return executing;
}

// Robot ATTACH () / DETACH () (dialect §7b): DETACH () gives the robot away; ATTACH () takes it
// when no other running task holds it.
void Scheduler::robot_attach(bool attach) {
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

// WAIT cond: the clock advances tick by tick until cond holds (bare WAIT: one tick).
// WAIT.EVENT , t: t seconds. Both wait for the motion first.
RunStatus Scheduler::wait(const Instr& in) {
  if (running_) return task_wait(in);
  if (const RunStatus s = arm_.finish_motion(); s != RunStatus::completed) return s;
  if (in.code == Code::wait_event) {
    const double t = to_real(vm_.eval(in.args[1]), "WAIT.EVENT time");
    if (!(t >= 0)) raise(Message::illegal_value, fmt::format("WAIT.EVENT {}", format_number(t)));
    return arm_.check_dwell(sim_.wait(t, vm_.step_of(in.line)), in.line);
  }
  if (in.args.empty()) {
    // One tick. Bare WAITs one after another with no time passing in between (a polling loop
    // `10 IF NOT SIG(1001) THEN` / `WAIT` / `GOTO 10`) are one wait: past Limits::max_wait_s it
    // stops as WAIT condition does, with the same hint (dialect §6).
    const double now = sim_.time_s();
    if (now != bare_wait_end_) bare_wait_start_ = now;
    if (now - bare_wait_start_ >= limits_.max_wait_s)
      return vm_.stop(fault(Message::wait_limit, fmt::format("a loop of WAIT still waiting after {} s{}",
                                                             format_number(limits_.max_wait_s), cell_.undriven_signals())));
    const RunStatus s = arm_.check_dwell(sim_.wait(limits_.tick_s, vm_.step_of(in.line)), in.line);
    bare_wait_end_ = sim_.time_s();
    return s;
  }
  const double give_up = sim_.time_s() + limits_.max_wait_s;
  cell_.begin_wait();
  while (to_real(vm_.eval(in.args[0]), "WAIT condition") == 0) {
    if (limits_.interrupt && limits_.interrupt->load(std::memory_order_relaxed)) {
      vm_.step_back();  // as between steps: PROCEED waits again
      return vm_.stop(fault(Message::interrupted));
    }
    if (sim_.time_s() >= give_up)
      return vm_.stop(fault(Message::wait_limit,
                            fmt::format("still false after {} s{}", format_number(limits_.max_wait_s), cell_.undriven_signals())));
    if (const RunStatus s = arm_.check_dwell(sim_.wait(limits_.tick_s, vm_.step_of(in.line)), in.line); s != RunStatus::completed)
      return s;
    if (!reactions().empty()) {  // a reaction due interrupts the wait, which goes on after it
      reactions().see([this](int k) { return cell_.signal_state(k); });
      if (reactions().due()) {
        vm_.step_back();
        return RunStatus::completed;
      }
    }
  }
  return RunStatus::completed;
}

// WAIT, WAIT.EVENT with tasks: the task gives way to the others until its time or condition.
// The robot task first lets its motion end (the step runs again at the motion's end).
RunStatus Scheduler::task_wait(const Instr& in) {
  if (robot_task()) {
    if (const RunStatus s = arm_.finish_motion(); s != RunStatus::completed) return s;
    if (sim_.time_s() > now_) {
      vm_.step_back();
      block_until(sim_.time_s());
      return RunStatus::completed;
    }
  }
  Task& t = *running_;
  if (in.code == Code::wait_event) {
    const double s = to_real(vm_.eval(in.args[1]), "WAIT.EVENT time");
    if (!(s >= 0)) raise(Message::illegal_value, fmt::format("WAIT.EVENT {}", format_number(s)));
    block_until(now_ + s);
    return RunStatus::completed;
  }
  if (in.args.empty()) {
    block_until(now_ + limits_.tick_s);
    return RunStatus::completed;
  }
  if (t.wait_since < 0) cell_.begin_wait();
  if (to_real(vm_.eval(in.args[0]), "WAIT condition") != 0) {
    t.wait_since = -1;
    return RunStatus::completed;
  }
  if (t.wait_since < 0) t.wait_since = now_;
  if (now_ - t.wait_since >= limits_.max_wait_s) {
    t.wait_since = -1;
    return vm_.stop(fault(Message::wait_limit,
                          fmt::format("still false after {} s{}", format_number(limits_.max_wait_s), cell_.undriven_signals())));
  }
  vm_.step_back();  // the condition is tested again when the task comes back
  block_until(now_ + limits_.tick_s);
  return RunStatus::completed;
}

// EXECUTE [n] prog(args): task n runs prog from now on; this task goes on. Arguments go by value.
void Scheduler::execute_task(const Instr& in) {
  const int n = in.args[0].kind == NodeKind::absent ? 0 : to_index(to_real(vm_.eval(in.args[0]), "task number"));
  if (n < 0 || n > kMaxTask) raise(Message::illegal_value, fmt::format("task {}", n));
  const auto& program = memory_.programs[static_cast<std::size_t>(in.program)];
  if (!program) raise(Message::undefined_name, in.target.text);
  if (!program->executable) raise(Message::not_executable, program->name);
  if (in.args.size() - 1 > program->params.size())
    raise(Message::illegal_value, fmt::format("{} takes {} arguments", program->name, program->params.size()));
  if (!running_) {  // the first EXECUTE: the running execution becomes task 0
    auto first = std::make_unique<Task>();
    first->program = vm_.run_program();
    first->globals = vm_.globals();
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
  Frame& top = t->stack.push_top(*program);
  for (std::size_t i = 1; i < in.args.size(); ++i)  // evaluated in the frame of the EXECUTE
    if (in.args[i].kind != NodeKind::absent) top.owned[i - 1].scalar = vm_.eval(in.args[i]);
  t->globals = vm_.globals();
  for (std::size_t slot = 0; slot < memory_.symbols.globals.size(); ++slot)  // its own LOCAL variables
    if (memory_.symbols.globals[slot].find('@') != std::string::npos) t->globals[slot] = &t->locals.emplace_back();
  auto at = std::find_if(tasks_.begin(), tasks_.end(), [&](const auto& other) { return other->number > n; });
  tasks_.insert(at, std::move(t));
  budget_.until = std::min(limits_.max_statements, budget_.done + kSliceStatements);
}

// ABORT n / KILL n end task n (its next step does not run); CYCLE.END n waits for its end;
// RELEASE gives way to the other tasks.
void Scheduler::task_instruction(const Instr& in) {
  const int n = in.args.empty() ? -1 : to_index(to_real(vm_.eval(in.args[0]), "task number"));
  Task* task = nullptr;
  for (const auto& t : tasks_)
    if (t->number == n) task = t.get();
  switch (in.io) {
    case IoOp::abort:
    case IoOp::kill:
      if (n == task_number()) {
        if (running_) running_->aborted = true;
        return vm_.stack().clear();
      }
      if (task) {
        task->done = task->aborted = true;
        task->stack.clear();
      }
      return;
    case IoOp::cycle_end:
      if (!task || task->done || task == running_) return;
      vm_.step_back();
      return block_until(now_ + limits_.tick_s);
    case IoOp::release:
      if (running_) block_until(now_);
      return;
    default: return;
  }
}

}  // namespace asimov::interpreter
