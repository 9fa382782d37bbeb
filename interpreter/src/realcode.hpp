// Real expressions compiled once at load time into a small tree of specialized functions
// (one per operator and operand kind: constants and variables are read in place, without a
// Value or a switch over node kinds). Only Node::plain trees of reals compile; the generic
// evaluator stays the reference: whatever the compiled code does not handle itself (an
// undefined variable, a string or location where a real was expected, an array used as a
// scalar, an index out of range) throws Fallback, and the caller evaluates the expression
// again generically, which reads the same variables and raises the exact error. Plain trees
// only read, so the second evaluation is safe.
#pragma once
#include "asimov/interpreter/values.hpp"
#include <memory>
#include <vector>

namespace asimov::interpreter {

struct Node;

// Thrown by compiled code: the generic evaluator takes over.
struct Fallback {};

// Where compiled code finds variables: the global slots and the running frame's slots.
struct FastCtx {
  Variable* const* globals = nullptr;
  Variable* const* slots = nullptr;
};

struct RStep;

struct RNode {
  using Fn = double (*)(const RNode&, const FastCtx&);
  Fn fn = nullptr;
  const RNode* a = nullptr;  // operands (binary), operand (unary), index (element), first (chain)
  const RNode* b = nullptr;
  const RStep* steps = nullptr;  // chain of more than one operator: `slot` steps
  double num = 0;            // constant
  int slot = 0;              // variable slot; chain: number of steps
};

// One operator of a chain and its right operand: acc = acc op operand. A chain of n operators
// runs as a loop over its steps (no recursion per operator, issue 17), each step a function
// specialized per operator and operand kind like the binary nodes.
struct RStep {
  using Fn = double (*)(double acc, const RStep&, const FastCtx&);
  Fn fn = nullptr;
  const RNode* operand = nullptr;
};

class RealCode {
 public:
  // The compiled expression, or null when `n` is not a plain real tree this form handles
  // (strings, locations, functions, several subscripts ...).
  static std::shared_ptr<const RealCode> compile(const Node& n);
  double run(const FastCtx& c) const { return root_->fn(*root_, c); }
  const RNode* root() const { return root_; }

  RealCode() = default;
  RealCode(const RealCode&) = delete;  // nodes point at each other
  RealCode& operator=(const RealCode&) = delete;

 private:
  const RNode* build(const Node& n);
  std::vector<RNode> nodes_;
  std::vector<RStep> steps_;  // the chains' steps, each chain's contiguous
  const RNode* root_ = nullptr;
};

// A variable's real value, or Fallback (undefined, another kind, an array).
// A variable never holds a scalar and elements at once (every store checks), so a scalar
// alone decides; the elements, a cache line further, are not read.
inline double real_of(const Variable& v) {
  if (v.scalar)
    if (const double* d = std::get_if<double>(&*v.scalar)) return *d;
  throw Fallback{};
}

// Index of a[i] for an index in 0 ... 65535 (to_index's rounding: halves away from zero),
// else Fallback (negative, too large, NaN: to_index and the generic path decide).
inline bool small_index(double x, int& k) {
  if (!(x >= 0 && x < 65535.5)) return false;
  k = static_cast<int>(x);  // x >= 0: truncation; x - k is exact
  k += x - k >= 0.5 ? 1 : 0;
  return true;
}
inline int fast_index(double x) {
  int k;
  if (!small_index(x, k)) throw Fallback{};
  return k;
}

}  // namespace asimov::interpreter
