#include "interpreter/evaluator.hpp"

#include "interpreter/errors.hpp"
#include "interpreter/limits.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <ostream>

namespace asimov::val {
namespace {

using ast::Op;

// Thrown by finish_motion() on contact; caught next to RuntimeError in run().
struct CollisionStop {
  motion::CollisionReport report;
};

double truth(bool b) { return b ? -1.0 : 0.0; }

std::int32_t to_int32(double x) {
  const double t = std::trunc(x);
  if (!(t >= -2147483648.0 && t <= 2147483647.0))
    raise(ErrorKind::illegal_value, fmt::format("{} is not a 32-bit integer", format_number(x)));
  return static_cast<std::int32_t>(t);
}

template <typename T>
bool compare(Op op, const T& a, const T& b) {
  switch (op) {
    case Op::eq: return a == b;
    case Op::ne: return a != b;
    case Op::lt: return a < b;
    case Op::gt: return a > b;
    case Op::le: return a <= b;
    case Op::ge: return a >= b;
    default: return false;
  }
}

bool is_relational(Op op) { return op >= Op::eq && op <= Op::ge; }

const char* op_text(Op op) {
  static constexpr const char* kText[] = {"-", "+", "NOT", "*", "/", "MOD", "+", "-", "==", "<>", "<",
                                          ">", "<=", ">=", "AND", "BAND", "OR", "XOR", "BOR", "BXOR", ":"};
  static_assert(std::size(kText) == static_cast<std::size_t>(Op::count));
  return kText[static_cast<std::size_t>(op)];
}

}  // namespace

Evaluator::Evaluator(motion::Simulator& sim, std::ostream& out, Memory& memory, const Limits& limits)
    : sim_(sim), out_(out), memory_(memory), limits_(limits) {}

RunResult Evaluator::run(int slot) {
  std::optional<Stopped> earlier = std::move(stopped_);  // a run keeps a stopped execution
  stopped_.reset();
  stack_.clear();
  speed_always_ = 100;  // each execution starts with SPEED 100 ALWAYS
  speed_next_.reset();
  current_program_ = nullptr;
  current_line_ = 0;
  motion_program_ = nullptr;
  last_motion_.reset();
  RunResult r = protected_run(memory_.symbols.programs[static_cast<std::size_t>(slot)], [&] {
    const auto& program = memory_.programs.at(static_cast<std::size_t>(slot));
    if (!program) raise(ErrorKind::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(slot)]);
    Frame top;
    top.program = program;
    for (std::size_t i = 0; i < program->params.size() + program->autos.size(); ++i) {
      top.owned.push_back(std::make_unique<Variable>());
      top.params.push_back(top.owned.back().get());
    }
    top.temps.resize(static_cast<std::size_t>(program->temps));
    stack_.push_back(std::move(top));
  });
  if (!stopped_) stopped_ = std::move(earlier);  // only the latest stopped execution is kept
  return r;
}

bool Evaluator::can_resume() const { return stopped_.has_value(); }

void Evaluator::abort() { stopped_.reset(); }

RunResult Evaluator::resume(bool retry) {
  if (!stopped_) {
    RunResult r;
    r.status = RunStatus::error;
    r.error.message = "*No program to resume*";
    return r;
  }
  Stopped s = std::move(*stopped_);
  stopped_.reset();
  stack_ = std::move(s.stack);
  speed_always_ = s.speed_always;
  speed_next_ = s.speed_next;
  last_motion_ = s.motion;
  return protected_run(s.program, [&] {
    // After a collision the step that found the contact runs again (PROCEED and RETRY);
    // RETRY after an error re-runs the failing step; PROCEED after an error skips it.
    if (!stack_.empty() && (retry || s.status == RunStatus::collision)) --stack_.back().pc;
    if (retry && s.status == RunStatus::collision && last_motion_) start_motion(*last_motion_);
  });
}

// --- the protected boundary -----------------------------------------------------------------

RunResult Evaluator::protected_run(const std::string& name, const std::function<void()>& setup) {
  RunResult result;
  statements_ = 0;
  warnings_.clear();
  memory_.globals.resize(memory_.symbols.globals.size());

  auto locate = [&](Diagnostic& d, const Program* p, int line) {
    if (!p) return;
    d.program = p->name;
    d.file = p->file;
    d.line = line;
    d.step = line - p->line;
    if (line >= 1 && static_cast<std::size_t>(line) <= p->text->size())
      d.source_line = (*p->text)[static_cast<std::size_t>(line - 1)];
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

  try {
    setup();
    while (!stack_.empty()) {
      Frame& f = stack_.back();
      if (f.pc >= static_cast<int>(f.program->code.size())) {  // .END returns
        stack_.pop_back();
        continue;
      }
      const Instr& in = f.program->code[static_cast<std::size_t>(f.pc)];
      current_program_ = f.program.get();
      current_line_ = in.line;
      // Ctrl-C: stop before this step, which PROCEED and RETRY then run.
      if (limits_.interrupt && limits_.interrupt->load(std::memory_order_relaxed))
        raise(ErrorKind::interrupted);
      ++f.pc;
      if (++statements_ > limits_.max_statements)
        raise(ErrorKind::too_many_statements, fmt::format("more than {}", limits_.max_statements));
      execute(in);
    }
    finish_motion();  // the last motion completes at the end of the run
  } catch (const RuntimeError& e) {
    result.status = RunStatus::error;
    result.error.message = e.message;
    result.error.detail = e.detail;
    locate(result.error, current_program_, current_line_);
    // The motion already started still completes (forward processing); contact wins.
    try {
      if (sim_.motion_pending()) {
        const motion::MotionResult r = sim_.finish_motion();
        if (r.status == motion::MotionStatus::collision) collided(r.collision);
      }
    } catch (...) {
    }
  } catch (const CollisionStop& c) {
    collided(c.report);
  }
  if (result.status == RunStatus::completed) {
    result.program = name;
    result.line = result.step = 0;
  } else if (!stack_.empty() || result.status == RunStatus::collision) {
    stopped_ = Stopped{std::move(stack_), result.status, name, speed_always_, speed_next_, last_motion_};
  }
  stack_.clear();
  result.warnings = std::move(warnings_);
  warnings_.clear();
  return result;
}

// --- statements -----------------------------------------------------------------------------

void Evaluator::execute(const Instr& in) {
  Frame& f = stack_.back();
  switch (in.code) {
    case Code::assign: {
      Value v = eval(in.args[0]);
      const char prefix = in.target.text[0];
      if (prefix == '$') {
        to_string_value(v);
      } else if (kind_of(v) == Kind::trans || kind_of(v) == Kind::ppoint) {
        raise(ErrorKind::illegal_value, "a location is assigned with SET");
      } else if (prefix == '#' || kind_of(v) != Kind::real) {
        raise(ErrorKind::illegal_value, fmt::format("{} cannot hold a {}", in.target.text, kind_name(kind_of(v))));
      }
      store(in.target, std::move(v));
      return;
    }
    case Code::set: {
      Value v = eval(in.args[0]);
      const Kind want = in.target.text[0] == '#' ? Kind::ppoint : Kind::trans;
      if (in.target.text[0] == '$' || kind_of(v) != want)
        raise(ErrorKind::illegal_value, fmt::format("{} cannot hold a {}", in.target.text, kind_name(kind_of(v))));
      store(in.target, std::move(v));
      return;
    }
    case Code::here:
      if (in.target.text[0] == '$') raise(ErrorKind::illegal_value, "HERE needs a location variable");
      if (in.target.text[0] == '#') store(in.target, sim_.joints());
      else store(in.target, sim_.here());
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
        raise(ErrorKind::illegal_value, "DECOMPOSE needs a real array");
      Variable& var = variable(in.target);
      if (var.scalar) raise(ErrorKind::illegal_value, fmt::format("{} is not an array", in.target.text));
      Index idx = in.target.subscripted ? index(in.target) : Index{0, 0, 0};
      const std::size_t last = in.target.kids.empty() ? 0 : in.target.kids.size() - 1;
      for (double p : parts) {
        if (idx[last] > kMaxArrayIndex) raise(ErrorKind::illegal_value, "index above 65535");
        var.elements[idx] = p;
        ++idx[last];
      }
      return;
    }
    case Code::type: return type(in);
    case Code::move: case Code::moves: case Code::appro: case Code::appros:
    case Code::depart: case Code::departs: case Code::ready: case Code::draw: case Code::align:
    case Code::drive:
      return motion(in);
    case Code::signal:  // SIGNAL n, ...: n > 0 on, n < 0 off, 0 ignored
      for (const Node& n : in.args) {
        const int k = signal_number(n, true);
        if (k > 0) memory_.signals.insert(k);
        if (k < 0) memory_.signals.erase(-k);
      }
      return;
    case Code::timer: {
      const int k = to_index(to_real(eval(in.args[0]), "timer number"));
      if (k < 1 || k > 16) raise(ErrorKind::illegal_value, fmt::format("timer {}", k));
      memory_.timers[static_cast<std::size_t>(k)] = {to_real(eval(in.args[1]), "TIMER value"), sim_.time_s()};
      return;
    }
    case Code::unsupported: {
      if (!in.always) raise(ErrorKind::not_supported, in.target.text);
      for (const Diagnostic& w : warnings_)
        if (w.detail == in.target.text) return;  // once per execution
      Diagnostic w;
      w.message = std::string(error_message(ErrorKind::not_supported));
      w.detail = in.target.text;
      w.warning = true;
      w.program = current_program_->name;
      w.file = current_program_->file;
      w.line = in.line;
      w.step = in.line - current_program_->line;
      w.source_line = (*current_program_->text)[static_cast<std::size_t>(in.line - 1)];
      warnings_.push_back(std::move(w));
      return;
    }
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
      if (in.args.empty()) sim_.set_tool(motion::Location::Identity());  // TOOL = TOOL NULL
      else sim_.set_tool(as_transformation(eval(in.args[0])));
      return;
    }
    case Code::base: {
      if (in.args.size() == 1 && in.args[0].kind != NodeKind::absent) {
        const Value v = eval(in.args[0]);
        if (kind_of(v) != Kind::real) {
          sim_.set_base(as_transformation(v));
          return;
        }
      }
      double x[4] = {0, 0, 0, 0};  // BASE dx, dy, dz, rz (omitted: 0)
      for (std::size_t k = 0; k < in.args.size(); ++k)
        if (in.args[k].kind != NodeKind::absent) x[k] = to_real(eval(in.args[k]), "BASE");
      sim_.set_base(motion::trans(x[0], x[1], x[2], x[3], 0, 0));
      return;
    }
    case Code::configure: {
      robots::ConfigurationRequest& r = sim_.request();
      switch (in.word) {
        case ast::Kw::righty: r.righty = 1; break;
        case ast::Kw::lefty: r.righty = 0; break;
        case ast::Kw::above: r.above = 1; break;
        case ast::Kw::below: r.above = 0; break;
        case ast::Kw::noflip: r.noflip = 1; break;
        case ast::Kw::flip: r.noflip = 0; break;
        case ast::Kw::single: r.single = true; break;
        case ast::Kw::multiple: r.single = false; break;
        default: break;
      }
      return;
    }
    case Code::break_: return finish_motion();
    case Code::speed: {
      const double s = to_real(eval(in.args[0]));
      if (!(s > 0 && s <= 100)) raise(ErrorKind::illegal_value, fmt::format("SPEED {}", format_number(s)));
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
      if (to_real(eval(in.args[0]), "condition") == 0) f.pc = in.jump;
      return;
    case Code::jump_true:
      if (to_real(eval(in.args[0]), "condition") != 0) f.pc = in.jump;
      return;
    case Code::for_init: {
      const double from = to_real(eval(in.args[0]));
      const double to = to_real(eval(in.args[1]));
      const double step = in.args.size() > 2 ? to_real(eval(in.args[2])) : 1.0;
      if (step == 0) raise(ErrorKind::illegal_value, "FOR with STEP 0");
      store(in.target, from);
      f.temps[static_cast<std::size_t>(in.temp)] = to;
      f.temps[static_cast<std::size_t>(in.temp) + 1] = step;
      if (step > 0 ? !(from <= to) : !(from >= to)) f.pc = in.jump;
      return;
    }
    case Code::for_next: {
      const double to = f.temps[static_cast<std::size_t>(in.temp)];
      const double step = f.temps[static_cast<std::size_t>(in.temp) + 1];
      const double v = finite(to_real(read(in.target)) + step);
      store(in.target, v);
      if (step > 0 ? v <= to : v >= to) f.pc = in.jump;
      return;
    }
    case Code::call: return call(in);
    case Code::return_: stack_.pop_back(); return;
    case Code::stop: stack_.clear(); return;
  }
}

void Evaluator::call(const Instr& in) {
  const auto& program = memory_.programs[static_cast<std::size_t>(in.program)];
  if (!program) raise(ErrorKind::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(in.program)]);
  if (static_cast<int>(stack_.size()) >= std::min(limits_.max_call_depth, kMaxCallDepth))
    raise(ErrorKind::too_many_calls, fmt::format("{} levels", stack_.size()));
  if (in.args.size() > program->params.size())
    raise(ErrorKind::illegal_value, fmt::format("{} takes {} arguments", program->name, program->params.size()));
  Frame frame;
  frame.program = program;
  for (std::size_t i = 0; i < program->params.size(); ++i) {
    const bool given = i < in.args.size() && in.args[i].kind != NodeKind::absent;
    if (given && in.by_ref[i]) {
      frame.params.push_back(&variable(in.args[i]));  // the caller's variable itself
      continue;
    }
    auto owned = std::make_unique<Variable>();
    if (given) owned->scalar = eval(in.args[i]);
    frame.params.push_back(owned.get());
    frame.owned.push_back(std::move(owned));
  }
  for (std::size_t i = 0; i < program->autos.size(); ++i) {  // a fresh AUTO copy per call
    frame.owned.push_back(std::make_unique<Variable>());
    frame.params.push_back(frame.owned.back().get());
  }
  frame.temps.resize(static_cast<std::size_t>(program->temps));
  stack_.push_back(std::move(frame));
}

void Evaluator::finish_motion() {
  if (!sim_.motion_pending()) return;
  const motion::MotionResult r = sim_.finish_motion();
  if (r.status == motion::MotionStatus::collision) throw CollisionStop{r.collision};
  if (r.status == motion::MotionStatus::error) {
    current_program_ = motion_program_;  // reported at the motion instruction
    current_line_ = motion_line_;
    raise_text(r.error.message, r.error.detail);
  }
}

void Evaluator::motion(const Instr& in) {
  finish_motion();  // a motion instruction waits for the previous motion to end
  const bool straight = in.code == Code::moves || in.code == Code::appros || in.code == Code::departs
      || in.code == Code::draw;
  std::optional<Value> target;
  switch (in.code) {
    case Code::ready: {  // the arm straight up: #PPOINT(0,-90,90,0,0,0)
      robots::JointVector j = robots::JointVector::Zero(sim_.robot().joint_count());
      if (j.size() >= 3) {
        j[1] = -90;
        j[2] = 90;
      }
      target = j;
      break;
    }
    case Code::align: {  // tool Z onto the nearest world axis (ties: Z, X, Y), smallest rotation
      motion::Location t = sim_.here();
      const Eigen::Vector3d z = t.linear().col(2);
      int axis = 2;
      if (std::fabs(z.x()) > std::fabs(z[axis])) axis = 0;
      if (std::fabs(z.y()) > std::fabs(z[axis])) axis = 1;
      const Eigen::Vector3d goal = Eigen::Vector3d::Unit(axis) * (z[axis] < 0 ? -1.0 : 1.0);
      const Eigen::Vector3d v = z.cross(goal);
      if (v.norm() > 1e-12)
        t.linear() = Eigen::AngleAxisd(std::atan2(v.norm(), z.dot(goal)), v.normalized()).toRotationMatrix() * t.linear();
      target = t;
      break;
    }
    case Code::drive: {  // DRIVE j, change, speed: one joint, relative, at speed % of its maximum
      const int j = to_index(to_real(eval(in.args[0]), "joint"));
      const double change = to_real(eval(in.args[1]), "DRIVE change");
      const double s = to_real(eval(in.args[2]), "DRIVE speed");
      if (j < 1 || j > sim_.robot().joint_count()) raise(ErrorKind::illegal_value, fmt::format("joint {}", j));
      if (!(s >= 1 && s <= 100)) raise(ErrorKind::illegal_value, fmt::format("DRIVE speed {}", format_number(s)));
      MotionRequest m;
      m.joints = sim_.joints();
      (*m.joints)[j - 1] += change;
      m.speed = {speed_monitor_, s};
      m.program = current_program_;
      m.line = in.line;
      return start_motion(m);  // the program speed does not apply and is not consumed
    }
    case Code::draw: {  // SHIFT(HERE BY dx, dy, dz), HERE after the previous motion
      motion::Location t = sim_.here();
      for (std::size_t k = 0; k < in.args.size(); ++k)
        if (in.args[k].kind != NodeKind::absent) t.translation()[static_cast<Eigen::Index>(k)] += to_real(eval(in.args[k]), "DRAW");
      target = t;
      break;
    }
    case Code::move: case Code::moves: target = eval(in.args[0]); break;
    case Code::appro: case Code::appros: {
      const Value loc = eval(in.args[0]);
      const double d = to_real(eval(in.args[1]), "APPRO distance");
      target = motion::Location(as_pose(loc, sim_) * motion::trans(0, 0, -d, 0, 0, 0));
      break;
    }
    default: {  // DEPART: HERE is taken once the previous motion has ended
      const double d = to_real(eval(in.args[0]), "DEPART distance");
      target = motion::Location(sim_.here() * motion::trans(0, 0, -d, 0, 0, 0));
      break;
    }
  }
  MotionRequest m;
  m.speed = {speed_monitor_, speed_next_.value_or(speed_always_)};
  speed_next_.reset();
  m.straight = straight;
  m.program = current_program_;
  m.line = in.line;
  if (const auto* j = std::get_if<robots::JointVector>(&*target); j && !straight) {
    m.joints = *j;
  } else {
    if (kind_of(*target) != Kind::trans && kind_of(*target) != Kind::ppoint)
      raise(ErrorKind::illegal_value, fmt::format("location expected, not a {}", kind_name(kind_of(*target))));
    m.pose = as_pose(*target, sim_);
  }
  start_motion(m);
}

// Starts a resolved motion (also RETRY's restart of an interrupted one).
void Evaluator::start_motion(const MotionRequest& m) {
  const int step = m.line - m.program->line;
  const motion::MotionResult r = m.joints ? sim_.start_joint_move(*m.joints, m.speed, step)
                                          : sim_.start_move(m.pose, m.straight, m.speed, step);
  motion_program_ = m.program;
  motion_line_ = m.line;
  last_motion_ = m;
  if (r.status == motion::MotionStatus::error) raise_text(r.error.message, r.error.detail);
  if (r.status == motion::MotionStatus::collision) throw CollisionStop{r.collision};
}

void Evaluator::type(const Instr& in) {
  bool newline = true;
  const std::string text = format_items(in.formats, in.args, newline);
  out_ << text;
  if (newline) out_ << '\n';
}

// The text of TYPE / $ENCODE items; `newline` is cleared by /S.
std::string Evaluator::format_items(const std::vector<ast::Format>& formats, const std::vector<Node>& values,
                                    bool& newline) {
  std::string text;
  bool after_number = false;  // the previous item was a number in default format
  ast::Format mode{'D', 0, 0};
  std::size_t next = 0;
  for (const ast::Format& item : formats) {
    switch (item.code) {
      case 0: {
        const Value v = eval(values[next++]);
        if (const auto* s = std::get_if<std::string>(&v)) {
          text += *s;
          after_number = false;
          break;
        }
        const double x = to_real(v, "TYPE item");
        if (mode.code == 'D') {
          if (after_number) text += ' ';
          text += format_number(x);
          after_number = true;
        } else {
          // A value that rounds to zero prints without a sign (-0.00 -> 0.00).
          const unsigned decimals = mode.code == 'F' ? std::min(mode.decimals, 15u) : 0u;
          const double shown = std::fabs(x) < 0.5 * std::pow(10.0, -static_cast<double>(decimals)) ? 0.0 : x;
          text += mode.code == 'F' ? fmt::format("{:>{}.{}f}", shown, mode.width, decimals)
                                   : fmt::format("{:>{}.0f}", std::round(shown), mode.width);
          after_number = false;
        }
        break;
      }
      case 'D': case 'F': case 'I': mode = item; break;
      case 'X': text.append(item.width, ' '); after_number = false; break;
      case 'C': text.append(item.width, '\n'); after_number = false; break;
      case 'S': newline = false; break;
      default: break;
    }
  }
  return text;
}

motion::Location Evaluator::as_transformation(const Value& v) {
  if (const auto* t = std::get_if<motion::Location>(&v)) return *t;
  raise(ErrorKind::illegal_value, fmt::format("transformation expected, not a {}", kind_name(kind_of(v))));
}

// --- expressions ----------------------------------------------------------------------------

Variable& Evaluator::variable(const Node& n) {
  if (n.ref.scope == Scope::global) return memory_.globals[static_cast<std::size_t>(n.ref.slot)];
  return *stack_.back().params[static_cast<std::size_t>(n.ref.slot)];
}

Index Evaluator::index(const Node& n) {
  Index idx{0, 0, 0};
  for (std::size_t i = 0; i < n.kids.size(); ++i) {
    const int k = to_index(to_real(eval(n.kids[i]), "index"));
    if (k < 0 || k > kMaxArrayIndex) raise(ErrorKind::illegal_value, fmt::format("index {} of {}", k, n.text));
    idx[i] = k;
  }
  return idx;
}

static std::string element_name(const Node& n, const Index& idx) {
  std::string s = n.text + "[";
  for (std::size_t i = 0; i < n.kids.size(); ++i) {
    if (i > 0) s += ',';
    s += std::to_string(idx[i]);
  }
  return s + "]";
}

Value Evaluator::read(const Node& n) {
  Variable& v = variable(n);
  if (!n.subscripted) {
    if (v.is_array()) raise(ErrorKind::illegal_value, fmt::format("{} is an array", n.text));
    if (!v.scalar) raise(ErrorKind::undefined_value, n.text);
    return *v.scalar;
  }
  if (n.kids.empty()) raise(ErrorKind::illegal_value, fmt::format("{}[] here", n.text));
  const Index idx = index(n);
  if (v.scalar) raise(ErrorKind::illegal_value, fmt::format("{} is not an array", n.text));
  const auto it = v.elements.find(idx);
  if (it == v.elements.end()) raise(ErrorKind::undefined_value, element_name(n, idx));
  return it->second;
}

void Evaluator::store(const Node& target, Value value) {
  Variable& v = variable(target);
  auto check_kind = [&](const Value& old) {
    if (kind_of(old) != kind_of(value))
      raise(ErrorKind::illegal_value, fmt::format("{} holds a {}, not a {}", target.text,
                                                  kind_name(kind_of(old)), kind_name(kind_of(value))));
  };
  if (!target.subscripted) {
    if (v.is_array()) raise(ErrorKind::illegal_value, fmt::format("{} is an array", target.text));
    if (v.scalar) check_kind(*v.scalar);
    v.scalar = std::move(value);
    return;
  }
  const Index idx = index(target);
  if (v.scalar) raise(ErrorKind::illegal_value, fmt::format("{} is not an array", target.text));
  if (!v.elements.empty()) check_kind(v.elements.begin()->second);
  v.elements[idx] = std::move(value);
}

bool Evaluator::defined(const Node& n) {
  const Variable& v = variable(n);
  if (!n.subscripted) return v.scalar.has_value();
  try {
    return v.elements.count(index(n)) > 0;
  } catch (const RuntimeError&) {
    return false;
  }
}

Value Evaluator::eval(const Node& n) {
  switch (n.kind) {
    case NodeKind::number: return n.number;
    case NodeKind::string: return n.text;
    case NodeKind::variable: return read(n);
    case NodeKind::unary: {
      const double x = to_real(eval(n.kids[0]), op_text(n.op));
      if (n.op == Op::neg) return -x + 0.0;
      if (n.op == Op::not_) return truth(x == 0);
      return x;
    }
    case NodeKind::binary: {
      const Value a = eval(n.kids[0]);  // both operands always: no short-circuit
      const Value b = eval(n.kids[1]);
      return binary(n.op, a, b);
    }
    case NodeKind::function: return function(n);
    case NodeKind::encode: {
      bool newline = true;
      std::string text = format_items(n.formats, n.kids, newline);
      if (text.size() > kMaxStringLength) raise(ErrorKind::illegal_value, "string longer than 128 characters");
      return text;
    }
    case NodeKind::absent: raise(ErrorKind::undefined_value, "omitted argument");
  }
  raise(ErrorKind::illegal_value, "bad expression");
}

// A signal number: outputs 1-512, inputs 1001-1512, soft signals 2001-2512 (negative: off).
int Evaluator::signal_number(const Node& n, bool output) {
  const int k = to_index(to_real(eval(n), "signal number"));
  const int a = std::abs(k);
  const bool out = a >= 1 && a <= 512, in = a >= 1001 && a <= 1512, soft = a >= 2001 && a <= 2512;
  if (k != 0 && !out && !in && !soft) raise(ErrorKind::illegal_value, fmt::format("signal {}", k));
  if (output && in) raise(ErrorKind::illegal_value, fmt::format("signal {} is an input", k));
  if (!output && k == 0) raise(ErrorKind::illegal_value, "signal 0");
  return k;
}

Value Evaluator::function(const Node& n) {
  if (n.func == Func::defined) return truth(defined(n.kids[0]));
  if (n.func == Func::sig) {  // TRUE when every listed condition holds
    bool all = true;
    for (const Node& k : n.kids) {
      const int s = signal_number(k, false);
      all = all && (memory_.signals.count(std::abs(s)) > 0) == (s > 0);
    }
    return truth(all);
  }
  if (n.func == Func::last) {  // the highest assigned first index, or -1
    const Variable& v = variable(n.kids[0]);
    return v.elements.empty() ? -1.0 : static_cast<double>(v.elements.rbegin()->first[0]);
  }
  if (n.func == Func::timer) {
    const int k = to_index(to_real(eval(n.kids[0]), "timer number"));
    if (k < 1 || k > 16) raise(ErrorKind::illegal_value, fmt::format("timer {}", k));
    const auto& [value, since] = memory_.timers[static_cast<std::size_t>(k)];
    return value + (sim_.time_s() - since);
  }
  std::vector<std::optional<Value>> args;
  args.reserve(n.kids.size());
  for (const Node& k : n.kids) {
    if (k.kind == NodeKind::absent) args.emplace_back();
    else args.emplace_back(eval(k));
  }
  return call_function(n.func, args, sim_);
}

Value Evaluator::binary(Op op, const Value& a, const Value& b) {
  if (op == Op::compound) {
    if (kind_of(a) != Kind::trans || kind_of(b) != Kind::trans)
      raise(ErrorKind::illegal_value, "\":\" needs two transformations");
    return motion::Location(std::get<motion::Location>(a) * std::get<motion::Location>(b));
  }
  if (kind_of(a) == Kind::string || kind_of(b) == Kind::string) {
    const std::string& x = to_string_value(a);
    const std::string& y = to_string_value(b);
    if (op == Op::add) {
      if (x.size() + y.size() > kMaxStringLength) raise(ErrorKind::illegal_value, "string longer than 128 characters");
      return x + y;
    }
    if (!is_relational(op)) raise(ErrorKind::illegal_value, fmt::format("\"{}\" on strings", op_text(op)));
    return truth(compare(op, x, y));
  }
  const double x = to_real(a, op_text(op));
  const double y = to_real(b, op_text(op));
  switch (op) {
    case Op::mul: return finite(x * y);
    case Op::div:
      if (y == 0) raise(ErrorKind::division_by_zero);
      return finite(x / y);
    case Op::mod:
      if (y == 0) raise(ErrorKind::division_by_zero);
      return finite(x - y * std::trunc(x / y));
    case Op::add: return finite(x + y);
    case Op::sub: return finite(x - y);
    case Op::and_: return truth(x != 0 && y != 0);
    case Op::or_: return truth(x != 0 || y != 0);
    case Op::xor_: return truth((x != 0) != (y != 0));
    case Op::band: return static_cast<double>(to_int32(x) & to_int32(y));
    case Op::bor: return static_cast<double>(to_int32(x) | to_int32(y));
    case Op::bxor: return static_cast<double>(to_int32(x) ^ to_int32(y));
    default: return truth(compare(op, x, y));
  }
}

}  // namespace asimov::val
