// Stage 3, values: variables (slots, elements, stores with their kind checks), expression
// evaluation (the generic path over Values, built-in functions) and the real fast paths (the
// compiled form of realcode.*, then try_real, then the generic path). Split from
// evaluator.cpp, which runs the statements.
#include "evaluator.hpp"

#include "errors.hpp"
#include "parser.hpp"
#include "limits.hpp"
#include "operators.hpp"
#include "terminal.hpp"
#include "time_decode.hpp"
#include "vplus_words.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace asimov::interpreter {

using ast::Op;

// --- expressions ----------------------------------------------------------------------------

Index Evaluator::index(const Node& n) {
  Index idx{0, 0, 0};
  for (std::size_t i = 0; i < n.kids.size(); ++i) {
    const double x = real(n.kids[i], "index");
    int k;
    if (!small_index(x, k)) k = to_index(x);
    if (k < 0 || k > kMaxArrayIndex) raise(Message::illegal_value, fmt::format("index {} of {}", k, n.text));
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

const Value& Evaluator::lookup(const Node& n) {
  Variable& v = variable(n);
  if (!n.subscripted) {
    if (v.is_array()) raise(Message::illegal_value, fmt::format("{} is an array", n.text));
    if (!v.scalar) raise(Message::undefined_value, n.text);
    return *v.scalar;
  }
  if (n.kids.empty()) raise(Message::illegal_value, fmt::format("{}[] here", n.text));
  const Index idx = index(n);
  if (v.scalar) raise(Message::illegal_value, fmt::format("{} is not an array", n.text));
  const Value* e = v.elements.get(idx);
  if (!e) raise(Message::undefined_value, element_name(n, idx));
  return *e;
}

void Evaluator::store(const Node& target, Value value) {
  Variable& v = variable(target);
  auto check_kind = [&](const Value& old) {
    if (kind_of(old) != kind_of(value))
      raise(Message::illegal_value, fmt::format("{} holds a {}, not a {}", target.text,
                                                  kind_name(kind_of(old)), kind_name(kind_of(value))));
  };
  if (!target.subscripted) {
    if (v.is_array()) raise(Message::illegal_value, fmt::format("{} is an array", target.text));
    if (v.scalar) check_kind(*v.scalar);
    v.scalar = std::move(value);
    return;
  }
  const Index idx = index(target);
  if (v.scalar) raise(Message::illegal_value, fmt::format("{} is not an array", target.text));
  if (!v.elements.empty()) check_kind(v.elements.begin()->second);
  v.elements.set(idx, std::move(value));
}

bool Evaluator::defined(const Node& n) {
  const Variable& v = variable(n);
  if (!n.subscripted) return v.scalar.has_value();
  try {
    return v.elements.count(index(n)) > 0;
  } catch (const Fault&) {
    return false;
  }
}

Value Evaluator::eval(const Node& n) {
  if (double x; run_fast(n, ctx_, x) || (n.plain && try_real(n, x))) return x;
  switch (n.kind) {
    case NodeKind::number: return n.number;
    case NodeKind::string: return n.text;
    case NodeKind::variable: return lookup(n);
    case NodeKind::unary: {
      const double x = to_real(eval(n.kids[0]), op_text(n.op));
      if (n.op == Op::neg) return -x + 0.0;
      if (n.op == Op::not_) return truth(x == 0);
      return x;
    }
    case NodeKind::chain: {  // left to right, both operands of each operator: no short-circuit
      Value a = eval(n.kids[0]);
      for (std::size_t i = 0; i < n.ops.size(); ++i) {
        const Value b = eval(n.kids[i + 1]);
        a = apply_binary(n.ops[i], a, b);
      }
      return a;
    }
    case NodeKind::function: return function(n);
    case NodeKind::encode: {
      bool newline = true;
      std::vector<Value> values;
      values.reserve(n.kids.size());
      for (const Node& k : n.kids) values.push_back(eval(k));
      std::string text = format_items(n.formats, values, newline);
      if (text.size() > kMaxStringLength) raise(Message::illegal_value, "string longer than 128 characters");
      return text;
    }
    case NodeKind::absent: raise(Message::undefined_value, "omitted argument");
  }
  raise(Message::illegal_value, "bad expression");
}

// A signal number: outputs 1-512, inputs 1001-1512, soft signals 2001-2512 (negative: off).
int Evaluator::signal_number(const Node& n, bool output) {
  const int k = to_index(to_real(eval(n), "signal number"));
  const int a = std::abs(k);
  const bool out = a >= 1 && a <= 512, in = a >= 1001 && a <= 1512, soft = a >= 2001 && a <= 2512;
  if (k != 0 && !out && !in && !soft) raise(Message::illegal_value, fmt::format("signal {}", k));
  if (output && in) raise(Message::illegal_value, fmt::format("signal {} is an input", k));
  if (!output && k == 0) raise(Message::illegal_value, "signal 0");
  return k;
}

Value Evaluator::function(const Node& n) {
  if (n.func == Func::defined) return truth(defined(n.kids[0]));
  if (n.func == Func::sig) {  // TRUE when every listed condition holds
    bool all = true;
    for (const Node& k : n.kids) {
      const int s = signal_number(k, false);
      all = all && cell_.signal_on(std::abs(s)) == (s > 0);
    }
    return truth(all);
  }
  if (n.func == Func::last) {  // the highest assigned first index, or -1
    const Variable& v = variable(n.kids[0]);
    return v.elements.empty() ? -1.0 : static_cast<double>(v.elements.rbegin()->first[0]);
  }
  if (n.func == Func::parameter) return parameter_value(n.kids[0].text, memory_.settings, sim_);
  if (n.func == Func::switch_) return truth(switch_value(n.kids[0].text, memory_.settings, sim_));
  if (n.func == Func::vplus) {  // dialect §13: the word and why
    const VplusWord* w = vplus_word(n.text, WordKind::function);
    raise(Message::not_supported, w ? vplus_refusal(*w) : n.text);
  }
  if (n.func == Func::pdest) return arm_.planned_destination();
  if (n.func == Func::priority) return static_cast<double>(sched_.reactions().priority());
  if (n.func == Func::state) return arm_.state(to_index(to_real(eval(n.kids[0]), "STATE selector")));
  if (n.func == Func::speed) return arm_.speed_factor(to_index(to_real(eval(n.kids[0]), "SPEED selector")));
  if (n.func == Func::time_s) {  // $TIME(): the controller's clock; $TIME(date, time): packed values
    const bool given = !n.kids.empty() && n.kids[0].kind != NodeKind::absent;
    if (!given) return time_text(std::time(nullptr));
    std::optional<double> time;
    if (n.kids.size() > 1 && n.kids[1].kind != NodeKind::absent) time = to_real(eval(n.kids[1]), "$TIME time");
    return time_text(to_real(eval(n.kids[0]), "$TIME date"), time);
  }
  if (n.func == Func::decode_s) {  // $DECODE(var, breaks, mode): takes the front of var
    const std::string breaks = to_string_value(eval(n.kids[1]));
    const double mode = to_real(eval(n.kids[2]), "$DECODE mode");
    std::string text = to_string_value(lookup(n.kids[0]));
    std::string taken = decode(text, breaks, mode);
    store(n.kids[0], Value(std::move(text)));
    return taken;
  }
  if (n.func == Func::task) {  // TASK(): this task; TASK(1, n): 4 while task n executes, else 0
    if (n.kids.empty()) return static_cast<double>(sched_.task_number());
    const int select = to_index(to_real(eval(n.kids[0]), "TASK selector"));
    const int task = n.kids.size() > 1 && n.kids[1].kind != NodeKind::absent
        ? to_index(to_real(eval(n.kids[1]), "task number")) : 0;
    if (select != 1) raise(Message::not_supported, fmt::format("TASK({}, ...)", select));
    return sched_.task_state(task);
  }
  if (n.func == Func::error) {  // ERROR(task [, select]): the last error's code, 0 when none
    for (const Node& k : n.kids)
      if (k.kind != NodeKind::absent) to_real(eval(k), "ERROR argument");
    return static_cast<double>(memory_.last_error);
  }
  if (n.func == Func::error_text) return error_text(to_index(to_real(eval(n.kids[0]), "error code")));
  if (n.func == Func::select) return 1.0;  // SELECT(ROBOT): the one robot
  if (n.func == Func::status) {  // STATUS("prog"): 0 not in memory, 1 loaded, 2 executing
    const std::string name = normalize_name(to_string_value(eval(n.kids[0])));
    const auto slot = memory_.symbols.program_slots.find(name);
    if (slot == memory_.symbols.program_slots.end() || !memory_.programs[static_cast<std::size_t>(slot->second)])
      return 0.0;
    return sched_.executing(name, run_program_) ? 2.0 : 1.0;
  }
  if (n.func == Func::iostat || n.func == Func::getc) return files_.function(n);  // dialect §7a
  if (n.func == Func::tas) {  // the old value (0 when undefined), then the new one is set
    const double old = defined(n.kids[0]) ? to_real(lookup(n.kids[0]), "TAS variable") : 0.0;
    store(n.kids[0], to_real(eval(n.kids[1]), "TAS value"));
    return old;
  }
  if (n.func == Func::timer) {  // TIMER(0) and negative: the simulated clock [assumption]
    const int k = to_index(to_real(eval(n.kids[0]), "timer number"));
    if (k <= 0) return sched_.clock();
    if (k > 16) raise(Message::illegal_value, fmt::format("timer {}", k));
    const auto& [value, since] = memory_.timers[static_cast<std::size_t>(k)];
    return value + (sched_.clock() - since);
  }
  std::vector<std::optional<Value>> args;
  args.reserve(n.kids.size());
  for (const Node& k : n.kids) {
    if (k.kind == NodeKind::absent) args.emplace_back();
    else args.emplace_back(eval(k));
  }
  return call_function(n.func, args, sim_);
}

// --- the real fast path -------------------------------------------------------------------

bool Evaluator::try_real(const Node& n, double& out) {
  switch (n.kind) {
    case NodeKind::number: out = n.number; return true;
    case NodeKind::variable: {
      if (!n.subscripted) {  // a scalar: no call (undefined and arrays go through lookup)
        const Variable& v = variable(n);
        if (v.scalar && !v.is_array()) {
          const double* d = std::get_if<double>(&*v.scalar);
          if (d) out = *d;
          return d != nullptr;
        }
      }
      const double* d = std::get_if<double>(&lookup(n));
      if (d) out = *d;
      return d != nullptr;
    }
    case NodeKind::unary: {
      double x;
      if (!try_real(n.kids[0], x)) return false;
      out = n.op == Op::neg ? -x + 0.0 : n.op == Op::not_ ? truth(x == 0) : x;
      return true;
    }
    case NodeKind::chain: {
      double a, b;
      const Node& l = n.kids[0];
      if (l.kind == NodeKind::number) a = l.number;  // constant operands without a call
      else if (!try_real(l, a)) return false;
      for (std::size_t i = 0; i < n.ops.size(); ++i) {
        const Node& r = n.kids[i + 1];
        if (r.kind == NodeKind::number) b = r.number;
        else if (!try_real(r, b)) return false;
        a = real_binary(n.ops[i], a, b);
      }
      out = a;
      return true;
    }
    default: return false;
  }
}

double Evaluator::real(const Node& n, const char* what) {
  if (double x; run_fast(n, ctx_, x) || (n.plain && try_real(n, x))) return x;
  return to_real(eval(n), what);
}

// Stores a real where one is already held (a scalar, or an element of a real array), in
// this frame; false when another case (a new element, an error) is left to store_real.
bool Evaluator::store_in_place(const Node& target, double x) {
  const Variable& v = *(target.ref.scope == Scope::global ? ctx_.globals : ctx_.slots)[target.ref.slot];
  if (!target.subscripted) {
    if (!v.scalar || !v.elements.empty()) return false;
    double* d = std::get_if<double>(&const_cast<Value&>(*v.scalar));
    if (d) *d = x;
    return d != nullptr;
  }
  double i;
  int k;
  if (target.kids.size() != 1 || v.scalar || !run_fast(target.kids[0], ctx_, i) || !small_index(i, k)) return false;
  Value* e = const_cast<Elements&>(v.elements).get(Index{k, 0, 0});
  double* d = e ? std::get_if<double>(e) : nullptr;  // an element of a real array
  if (d) *d = x;
  return d != nullptr;
}

// store() for a real, without building a Value; the same errors.
void Evaluator::store_real(const Node& target, double x) {
  Variable& v = variable(target);
  if (!target.subscripted) {
    if (!v.elements.empty()) return store(target, x);  // the error
    if (!v.scalar) v.scalar.emplace(x);
    else if (double* d = std::get_if<double>(&*v.scalar)) *d = x;
    else store(target, x);  // the error
    return;
  }
  const Index idx = index(target);
  if (v.scalar) raise(Message::illegal_value, fmt::format("{} is not an array", target.text));
  if (!v.elements.empty() && kind_of(v.elements.begin()->second) != Kind::real)
    raise(Message::illegal_value, fmt::format("{} holds a {}, not a real", target.text,
                                                kind_name(kind_of(v.elements.begin()->second))));
  if (Value* e = v.elements.get(idx)) *e = x;
  else v.elements.set(idx, x);
}

}  // namespace asimov::interpreter
