// Stage 3, the arm (arm_controller.hpp): motion instructions resolved to requests and started
// on the simulator, the hand, the speed and duration settings, the checks of a finished motion
// (contact, motion error, Ctrl-C, a REACTI's stop) and the resume of a halted motion.
#include "arm_controller.hpp"

#include "evaluator.hpp"
#include "limits.hpp"
#include "operators.hpp"
#include "settings.hpp"
#include "asimov/motion/targets.hpp"
#include "asimov/robots/robot.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace asimov::interpreter {

void ArmController::begin_run() {
  settings_ = ArmSettings{};  // each execution starts with SPEED 100 ALWAYS and no DURATION
  motion_program_ = nullptr;
  last_motion_.reset();
}

void ArmController::begin_resume(const ArmSettings& settings, std::optional<MotionRequest> motion) {
  settings_ = settings;
  last_motion_ = std::move(motion);
}

void ArmController::begin_records() {
  motion_sites_.clear();
  motion_times_.clear();
  motion_times_omitted_ = 0;
  halt_.reset();
}

void ArmController::end_records(RunResult& result) {
  result.interrupt = halt_;
  result.motion_times = std::move(motion_times_);
  result.motion_times_omitted = motion_times_omitted_;
  motion_times_.clear();
  for (const auto& [program, line] : motion_sites_) {
    Diagnostic at;
    locate_at(at, *program, line);
    at.source_line.erase(0, at.source_line.find_first_not_of(" \t"));
    result.motions.push_back({at.step, at.program, line, std::move(at.source_line)});
  }
}

// --- statements -----------------------------------------------------------------------------

RunStatus ArmController::hand(const Instr& in) {
  using motion::HandState;
  const ast::Kw w = in.word;
  const HandState h = w == ast::Kw::open || w == ast::Kw::openi     ? HandState::open
                      : w == ast::Kw::close || w == ast::Kw::closei ? HandState::closed
                                                                    : HandState::relaxed;
  vm_.scheduler().require_robot();
  if (w == ast::Kw::open || w == ast::Kw::close || w == ast::Kw::relax) {
    sim_.request_hand(h);
    return RunStatus::completed;
  }
  // The hand acts where the motion ended, then HAND.TIME.
  if (const RunStatus s = check_motion(sim_.finish_motion()); s != RunStatus::completed) return s;
  cell_.hand_changed(h, in.line);
  return check_dwell(sim_.hand_immediate(h, memory_.settings.hand_time_s, vm_.step_of(in.line)), in.line);  // OPENI ...
}

void ArmController::setting(const Instr& in) {
  switch (in.code) {
    case Code::accel: {  // ACCEL (profile) a, d: an omitted one is kept; out of [1, 100]: the nearer end
      if (in.args[0].kind != NodeKind::absent) to_real(vm_.eval(in.args[0]), "ACCEL profile");  // profile 0 is used
      Settings& s = memory_.settings;
      double* ramp[2] = {&s.accel, &s.decel};
      for (std::size_t k = 1; k < in.args.size(); ++k)
        if (in.args[k].kind != NodeKind::absent)
          *ramp[k - 1] = std::clamp(to_real(vm_.eval(in.args[k]), k == 1 ? "ACCEL acceleration" : "ACCEL deceleration"), 1.0, 100.0);
      return;
    }
    case Code::duration: {
      const double t = to_real(vm_.eval(in.args[0]), "DURATION");
      if (!(t >= 0)) raise(Message::illegal_value, fmt::format("DURATION {}", format_number(t)));
      if (in.scope == SpeedScope::always) settings_.duration_always = t, settings_.duration_next.reset();
      else settings_.duration_next = t;
      return;
    }
    case Code::tool: {
      vm_.scheduler().require_robot();
      if (in.args.empty()) sim_.settings().tool = motion::Location::Identity();  // TOOL = TOOL NULL
      else sim_.settings().tool = as_transformation(vm_.eval(in.args[0]));
      return;
    }
    case Code::base: {
      vm_.scheduler().require_robot();
      if (in.args.size() == 1 && in.args[0].kind != NodeKind::absent) {
        const Value v = vm_.eval(in.args[0]);
        if (kind_of(v) != Kind::real) {
          sim_.settings().base = as_transformation(v);
          return;
        }
      }
      double x[4] = {0, 0, 0, 0};  // BASE dx, dy, dz, rz (omitted: 0)
      for (std::size_t k = 0; k < in.args.size(); ++k)
        if (in.args[k].kind != NodeKind::absent) x[k] = to_real(vm_.eval(in.args[k]), "BASE");
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
        vm_.warn_once(std::string(name) + " (no meaning for this arm: ignored)", in);
      return request_configuration(in.word, sim_.settings().request);
    }
    case Code::speed: {
      const double s = to_real(vm_.eval(in.args[0]));
      if (!(s > 0 && s <= 100)) raise(Message::illegal_value, fmt::format("SPEED {}", format_number(s)));
      if (in.scope == SpeedScope::monitor) {
        speed_monitor_ = s;
      } else if (in.scope == SpeedScope::always) {
        settings_.speed_always = s;
        settings_.speed_next.reset();
      } else {
        settings_.speed_next = s;
      }
      return;
    }
    default: return;
  }
}

RunStatus ArmController::finish_motion() {
  if (!sim_.motion_pending()) return RunStatus::completed;
  const RunStatus s = check_motion(sim_.finish_motion());
  moving_until_ = sim_.time_s();  // for the other tasks the arm moves until then (STATE(2))
  return s;
}

// The motion that the simulator finished failed: contact stops the run, an error is reported
// at the motion instruction.
RunStatus ArmController::check_motion(const motion::MotionResult& r) {
  switch (r.status) {
    case motion::MotionStatus::ok: return RunStatus::completed;
    case motion::MotionStatus::collision: contact_ = r.collision; return RunStatus::collision;
    case motion::MotionStatus::interrupted:
      if (r.interrupt.by_condition) {  // a REACTI: the step waiting for the motion runs again later
        vm_.scheduler().braked(r.interrupt);
        throw Braked{};
      }
      // Ctrl-C halted the motion: reported at the motion instruction, as a contact is; the step
      // that was waiting for the motion (none at the run's end) runs again after its rest.
      halt_ = r.interrupt;
      vm_.step_back();
      vm_.locate(motion_program_, motion_line_);
      return vm_.stop(fault(Message::interrupted));
    case motion::MotionStatus::error:
      vm_.locate(motion_program_, motion_line_);  // reported at the motion instruction
      return vm_.stop(Fault{Message::motion, r.error.message, r.error.detail});
  }
  return RunStatus::completed;
}

RunStatus ArmController::check_dwell(const motion::MotionResult& r, int line) {
  if (r.status == motion::MotionStatus::interrupted && r.interrupt.waiting) {
    // Ctrl-C in a wait with parts moving (WAIT.EVENT, a dwell): no motion halted, nothing to
    // resume; reported at the statement that waited, which runs again on PROCEED.
    vm_.step_back();
    return vm_.stop(fault(Message::interrupted));
  }
  if (r.status == motion::MotionStatus::collision) {  // located at the statement that waited
    motion_program_ = vm_.current_program();
    motion_line_ = line;
  }
  return check_motion(r);
}

RunStatus ArmController::motion(const Instr& in) {
  vm_.scheduler().require_robot();
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
      const int j = to_index(to_real(vm_.eval(in.args[0]), "joint"));
      const double change = to_real(vm_.eval(in.args[1]), "DRIVE change");
      const double s = to_real(vm_.eval(in.args[2]), "DRIVE speed");
      if (!(s >= 1 && s <= 100)) raise(Message::illegal_value, fmt::format("DRIVE speed {}", format_number(s)));
      robots::JointVector target;
      if (!motion::drive_target(sim_.planned_joints(), j, change, target))
        raise(Message::illegal_value, fmt::format("joint {}", j));
      MotionRequest m;
      m.joints = target;
      m.speed = motion::drive_speed(speed_monitor_, s);
      m.program = vm_.current_program();
      m.line = in.line;
      return start_motion(m);  // the program speed does not apply and is not consumed
    }
    case Code::draw: {  // SHIFT(HERE BY dx, dy, dz), HERE after the previous motion; omitted = 0
      double d[3] = {0, 0, 0};
      for (std::size_t k = 0; k < in.args.size() && k < 3; ++k)
        if (in.args[k].kind != NodeKind::absent) d[k] = to_real(vm_.eval(in.args[k]), "DRAW");
      target = motion::draw_target(sim_.planned_here(), d[0], d[1], d[2]);
      break;
    }
    case Code::move: case Code::moves: target = vm_.eval(in.args[0]); break;
    case Code::movet: case Code::movest: {  // the hand opens (h != 0) or closes when it starts
      target = vm_.eval(in.args[0]);
      sim_.request_hand(motion::movet_hand(to_real(vm_.eval(in.args[1]), "MOVET hand")));
      break;
    }
    case Code::appro: case Code::appros: {
      const Value loc = vm_.eval(in.args[0]);
      const double d = to_real(vm_.eval(in.args[1]), "APPRO distance");
      target = motion::appro_target(as_pose(loc, sim_), d);
      break;
    }
    case Code::depart: case Code::departs: {  // from where the previous motion ends
      const double d = to_real(vm_.eval(in.args[0]), "DEPART distance");
      target = motion::depart_target(sim_.planned_here(), d);
      break;
    }
    default: raise(Message::not_supported, "a motion without a target in ArmController::motion");
  }
  MotionRequest m;
  m.speed = {speed_monitor_, settings_.speed_next.value_or(settings_.speed_always), -1,
             settings_.duration_next.value_or(settings_.duration_always)};
  m.straight = straight;
  m.program = vm_.current_program();
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
  settings_.speed_next.reset();
  settings_.duration_next.reset();
  return s;
}

// PROCEED / RETRY after Ctrl-C halted a motion: the rest of it, from where the arm stopped;
// when a DO has moved the arm since (the simulator dropped the rest), the same motion
// instruction again from where the arm is. The monitor speed now in effect applies.
RunStatus ArmController::resume_halted_motion() {
  if (!last_motion_) return RunStatus::completed;
  motion_program_ = last_motion_->program;
  motion_line_ = last_motion_->line;
  if (sim_.halted_motion()) return check_motion(sim_.resume_motion(speed_monitor_));
  MotionRequest m = *last_motion_;
  m.speed.monitor = speed_monitor_;
  return start_motion(m);
}

// Starts a resolved motion (also RETRY's restart of an interrupted one).
RunStatus ArmController::start_motion(const MotionRequest& m) {
  const int step = m.line - m.program->line;
  if (std::find(motion_sites_.begin(), motion_sites_.end(), std::pair{m.program, m.line}) == motion_sites_.end())
    motion_sites_.emplace_back(m.program, m.line);
  // OPEN / CLOSE act as this motion starts: the grasp or release where the previous motion
  // ended (a stop, also with continuous path), before this one is planned (a carried part
  // widens its step bounds).
  const std::optional<motion::HandState> hand_request = sim_.hand().pending;
  if (hand_request && sim_.cell_runtime()) {
    if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
    cell_.hand_changed(*hand_request, m.line);
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
    return vm_.stop(Fault{Message::motion, r.error.message, r.error.detail});
  if (const auto timing = sim_.pending_timing()) {
    record_timing(*timing, m.program->name);
    earlier_destination_ = std::move(earlier);
    earlier_until_ = timing->start_s;
  }
  return RunStatus::completed;
}

void ArmController::record_timing(const motion::MotionTiming& t, const std::string& program) {
  if (motion_times_.size() >= kMaxMotionTimes) {
    ++motion_times_omitted_;
    return;
  }
  motion_times_.push_back({t.step, program, t.start_s, t.duration_s, t.blended});
}

// A REACTI stopped the motion: the rest is dropped (V+ does not resume it; the next motion
// starts from here).
void ArmController::braked() {
  sim_.drop_halted_motion();
  moving_until_ = sim_.time_s();
}

// --- what the other parts see -----------------------------------------------------------------

bool ArmController::moving() const {
  const Scheduler& tasks = vm_.scheduler();
  return sim_.motion_pending() || (tasks.tasks_running() && tasks.now() < moving_until_);
}

// #PDEST: the joints the motion in progress ends at, the arm's joints when none is. The
// simulator plans (and, blending, carries out) motions ahead of the task clock: a task that runs
// before the pending motion's start sees the motion before it, which ends where it starts.
robots::JointVector ArmController::planned_destination() const {
  const Scheduler& tasks = vm_.scheduler();
  if (tasks.tasks_running() && sim_.motion_pending() && tasks.now() < earlier_until_) return earlier_destination_;
  return sim_.planned_joints();
}

// STATE(select) as the simulated controller reports it (dialect §7): power on and calibrated,
// under program control, no front-panel flag, automatic mode.
double ArmController::state(int select) const {
  switch (select) {
    case 1: return 7;  // robot under program control
    case 2: return moving() ? 1 : motion_program_ ? 2 : 0;  // moving / at its target / no motion yet
    case 3: return 5;  // the manual control mode: computer control enabled (no pendant)
    case 4: return 0;  // no front-panel or hardware flag (the E-stop bit 4 is clear)
    case 5: return 1;  // automatic mode
    case 9: return moving() ? 1 : 0;  // a motion under way
    default: raise(Message::not_supported, fmt::format("STATE({})", select));
  }
}

// SPEED(select) [assumption: the selectors as recalled from the V+ reference, dialect §7]:
// 1 the monitor speed, 2 the program speed set with ALWAYS, 3 the speed of the next motion (a
// SPEED without ALWAYS not used yet, else 2's).
double ArmController::speed_factor(int select) const {
  switch (select) {
    case 1: return speed_monitor_;
    case 2: return settings_.speed_always;
    case 3: return settings_.speed_next.value_or(settings_.speed_always);
    default: raise(Message::not_supported, fmt::format("SPEED({})", select));
  }
}

}  // namespace asimov::interpreter
