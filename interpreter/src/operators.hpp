// The binary operators of dialect §3 on evaluated values: arithmetic with checked results,
// relational (numbers and strings), logical (TRUE = -1), bitwise on 32-bit integers, and the
// compound ':' of two transformations.
#pragma once
#include "ast.hpp"
#include "asimov/interpreter/values.hpp"
#include <cmath>
#include <cstdint>

namespace asimov::interpreter {

inline double truth(bool b) { return b ? -1.0 : 0.0; }

// The operator as written, for messages.
const char* op_text(ast::Op op);

Value apply_binary(ast::Op op, const Value& a, const Value& b);

// Bitwise operands: truncated to 32-bit signed integers; outside is an *Illegal value*.
std::int32_t to_int32(double x);
[[noreturn]] void raise_division_by_zero();

// Any operator but ':' on two reals (inline: the evaluator's fast path).
inline double real_binary(ast::Op op, double x, double y) {
  using ast::Op;
  switch (op) {
    case Op::mul: return finite(x * y);
    case Op::div:
      if (y == 0) raise_division_by_zero();
      return finite(x / y);
    case Op::mod:
      if (y == 0) raise_division_by_zero();
      return finite(x - y * std::trunc(x / y));
    case Op::add: return finite(x + y);
    case Op::sub: return finite(x - y);
    case Op::and_: return truth(x != 0 && y != 0);
    case Op::or_: return truth(x != 0 || y != 0);
    case Op::xor_: return truth((x != 0) != (y != 0));
    case Op::band: return static_cast<double>(to_int32(x) & to_int32(y));
    case Op::bor: return static_cast<double>(to_int32(x) | to_int32(y));
    case Op::bxor: return static_cast<double>(to_int32(x) ^ to_int32(y));
    case Op::eq: return truth(x == y);
    case Op::ne: return truth(x != y);
    case Op::lt: return truth(x < y);
    case Op::gt: return truth(x > y);
    case Op::le: return truth(x <= y);
    case Op::ge: return truth(x >= y);
    default: return finite(x);  // unary operators and ':' never reach here
  }
}

}  // namespace asimov::interpreter
