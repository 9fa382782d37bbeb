#include "realcode.hpp"

#include "code.hpp"
#include "operators.hpp"

#include <array>
#include <cstdint>
#include <utility>

namespace asimov::interpreter {
namespace {

using ast::Op;

// How an operand is read: through its own function, or in place.
enum class K : int { node, num, global, param, count };

template <K k>
inline double get(const RNode* p, const FastCtx& c) {
  if constexpr (k == K::num) return p->num;
  else if constexpr (k == K::global) return real_of(*c.globals[p->slot]);
  else if constexpr (k == K::param) return real_of(*c.slots[p->slot]);
  else return p->fn(*p, c);
}

template <K k>
double leaf(const RNode& n, const FastCtx& c) { return get<k>(&n, c); }

// a[i]: one subscript, the element in the array's dense table.
template <Scope s, K i>
double element(const RNode& n, const FastCtx& c) {
  const int k = fast_index(get<i>(n.a, c));
  const Variable& v = *(s == Scope::global ? c.globals : c.slots)[n.slot];
  if (v.scalar) throw Fallback{};
  const Value* e = const_cast<Elements&>(v.elements).get(Index{k, 0, 0});
  if (!e) throw Fallback{};
  if (const double* d = std::get_if<double>(e)) return *d;
  throw Fallback{};
}

// The same as Evaluator::eval's unary case on a real.
template <Op op, K x>
double unary(const RNode& n, const FastCtx& c) {
  const double v = get<x>(n.a, c);
  if constexpr (op == Op::neg) return -v + 0.0;
  else if constexpr (op == Op::not_) return truth(v == 0);
  else return v;
}

// MOD of two integers in int32 (not INT32_MIN, divisor not 0) in integer arithmetic: the
// same result as real_binary's x - y * trunc(x / y). There |x / y| is at least 1/|y| away
// from any integer it does not equal, far more than the rounding of the division (|x| < 2^31),
// so trunc sees the exact quotient; y * q and the difference are exact integers below 2^31,
// and a zero remainder is +0 both ways. Integer division is shorter than the divide, truncate
// and multiply chain on doubles.
inline bool int_mod(double x, double y, double& out) {
  const auto a = static_cast<std::int32_t>(x), b = static_cast<std::int32_t>(y);
  if (static_cast<double>(a) != x || static_cast<double>(b) != y || b == 0 || a == INT32_MIN || b == INT32_MIN)
    return false;
  out = static_cast<double>(a % b);
  return true;
}

template <Op op>
inline double apply(double x, double y) {
  if constexpr (op == Op::mod)
    if (double m; x > -2147483648.0 && x < 2147483648.0 && y > -2147483648.0 && y < 2147483648.0 && int_mod(x, y, m))
      return m;
  return real_binary(op, x, y);
}

template <Op op, K l, K r>
double binary(const RNode& n, const FastCtx& c) {
  const double x = get<l>(n.a, c);  // left before right, as the generic path
  return apply<op>(x, get<r>(n.b, c));
}

// acc op operand, one step of a chain (binary with the left side already known).
template <Op op, K r>
double step(double x, const RStep& s, const FastCtx& c) { return apply<op>(x, get<r>(s.operand, c)); }

// A chain of more than one operator: left to right, as the generic path.
template <K first>
double chain(const RNode& n, const FastCtx& c) {
  double x = get<first>(n.a, c);
  for (const RStep *s = n.steps, *end = n.steps + n.slot; s != end; ++s) x = s->fn(x, *s, c);
  return x;
}

constexpr int kKinds = static_cast<int>(K::count);
constexpr int kOps = static_cast<int>(Op::compound);  // every operator but ':'

template <int... I>
constexpr auto binary_table(std::integer_sequence<int, I...>) {
  return std::array<RNode::Fn, sizeof...(I)>{
      &binary<static_cast<Op>(I / (kKinds * kKinds)), static_cast<K>(I / kKinds % kKinds), static_cast<K>(I % kKinds)>...};
}
constexpr auto kBinary = binary_table(std::make_integer_sequence<int, kOps * kKinds * kKinds>{});

template <int... I>
constexpr auto step_table(std::integer_sequence<int, I...>) {
  return std::array<RStep::Fn, sizeof...(I)>{&step<static_cast<Op>(I / kKinds), static_cast<K>(I % kKinds)>...};
}
constexpr auto kStep = step_table(std::make_integer_sequence<int, kOps * kKinds>{});

template <int... I>
constexpr auto chain_row(std::integer_sequence<int, I...>) {
  return std::array<RNode::Fn, kKinds>{&chain<static_cast<K>(I)>...};
}
constexpr auto kChain = chain_row(std::make_integer_sequence<int, kKinds>{});

template <Op op, int... I>
constexpr auto unary_row(std::integer_sequence<int, I...>) {
  return std::array<RNode::Fn, kKinds>{&unary<op, static_cast<K>(I)>...};
}
constexpr auto kNeg = unary_row<Op::neg>(std::make_integer_sequence<int, kKinds>{});
constexpr auto kNot = unary_row<Op::not_>(std::make_integer_sequence<int, kKinds>{});
constexpr auto kPlus = unary_row<Op::plus>(std::make_integer_sequence<int, kKinds>{});

template <Scope s, int... I>
constexpr auto element_row(std::integer_sequence<int, I...>) {
  return std::array<RNode::Fn, kKinds>{&element<s, static_cast<K>(I)>...};
}
constexpr auto kGlobalElement = element_row<Scope::global>(std::make_integer_sequence<int, kKinds>{});
constexpr auto kParamElement = element_row<Scope::param>(std::make_integer_sequence<int, kKinds>{});

bool real_variable(const Node& n) { return n.text.empty() || (n.text[0] != '$' && n.text[0] != '#'); }

// Nodes the compiled form handles, and how many RNodes they take (and chain steps, added to
// `steps`); -1 for a node it does not handle.
long count(const Node& n, long& steps) {
  switch (n.kind) {
    case NodeKind::number: return 1;
    case NodeKind::variable:
      if (!real_variable(n)) return -1;
      if (!n.subscripted) return 1;
      if (n.kids.size() != 1) return -1;
      if (const long k = count(n.kids[0], steps); k > 0) return k + 1;
      return -1;
    case NodeKind::unary:
      if (n.kids.size() != 1) return -1;
      if (const long k = count(n.kids[0], steps); k > 0) return k + 1;
      return -1;
    case NodeKind::chain: {
      if (n.ops[0] == Op::compound || n.kids.size() != n.ops.size() + 1) return -1;
      long total = 1;
      for (const Node& k : n.kids) {
        const long c = count(k, steps);
        if (c <= 0) return -1;
        total += c;
      }
      if (n.ops.size() > 1) steps += static_cast<long>(n.ops.size());
      return total;
    }
    default: return -1;
  }
}

K kind(const Node& n) {
  if (n.kind == NodeKind::number) return K::num;
  if (n.kind == NodeKind::variable && !n.subscripted) return n.ref.scope == Scope::global ? K::global : K::param;
  return K::node;
}

}  // namespace

std::shared_ptr<const RealCode> RealCode::compile(const Node& n) {
  if (!n.plain) return nullptr;
  long steps = 0;
  const long size = count(n, steps);
  if (size <= 0) return nullptr;
  auto code = std::make_shared<RealCode>();
  code->nodes_.reserve(static_cast<std::size_t>(size));  // no reallocation: nodes point at each other
  code->steps_.reserve(static_cast<std::size_t>(steps));
  code->root_ = code->build(n);
  return code;
}

const RNode* RealCode::build(const Node& n) {
  RNode r;
  switch (n.kind) {
    case NodeKind::number:
      r.num = n.number;
      r.fn = &leaf<K::num>;
      break;
    case NodeKind::variable:
      r.slot = n.ref.slot;
      if (!n.subscripted) {
        r.fn = n.ref.scope == Scope::global ? &leaf<K::global> : &leaf<K::param>;
      } else {
        r.a = build(n.kids[0]);
        const auto i = static_cast<std::size_t>(kind(n.kids[0]));
        r.fn = n.ref.scope == Scope::global ? kGlobalElement[i] : kParamElement[i];
      }
      break;
    case NodeKind::unary: {
      r.a = build(n.kids[0]);
      const auto i = static_cast<std::size_t>(kind(n.kids[0]));
      r.fn = n.op == Op::neg ? kNeg[i] : n.op == Op::not_ ? kNot[i] : kPlus[i];
      break;
    }
    default: {  // chain
      r.a = build(n.kids[0]);
      if (n.ops.size() == 1) {  // one operator: a binary node, both operand kinds specialized
        r.b = build(n.kids[1]);
        const int i = (static_cast<int>(n.ops[0]) * kKinds + static_cast<int>(kind(n.kids[0]))) * kKinds
            + static_cast<int>(kind(n.kids[1]));
        r.fn = kBinary[static_cast<std::size_t>(i)];
        break;
      }
      // The operands first (their own chains take their steps), then this chain's steps in
      // one contiguous run.
      std::vector<RStep> mine(n.ops.size());
      for (std::size_t k = 0; k < n.ops.size(); ++k) {
        const Node& operand = n.kids[k + 1];
        mine[k].operand = build(operand);
        mine[k].fn = kStep[static_cast<std::size_t>(static_cast<int>(n.ops[k]) * kKinds + static_cast<int>(kind(operand)))];
      }
      r.steps = steps_.data() + steps_.size();
      r.slot = static_cast<int>(mine.size());
      steps_.insert(steps_.end(), mine.begin(), mine.end());
      r.fn = kChain[static_cast<std::size_t>(kind(n.kids[0]))];
      break;
    }
  }
  nodes_.push_back(r);
  return &nodes_.back();
}

}  // namespace asimov::interpreter
