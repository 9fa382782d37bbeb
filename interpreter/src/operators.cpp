#include "operators.hpp"

#include "errors.hpp"
#include "functions.hpp"
#include "limits.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <iterator>

namespace asimov::interpreter {

using ast::Op;

namespace {

}  // namespace

std::int32_t to_int32(double x) {
  const double t = std::trunc(x);
  if (!(t >= -2147483648.0 && t <= 2147483647.0))
    raise(Message::illegal_value, fmt::format("{} is not a 32-bit integer", format_number(x)));
  return static_cast<std::int32_t>(t);
}

namespace {

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

}  // namespace

const char* op_text(Op op) {
  static constexpr const char* kText[] = {"-", "+", "NOT", "*", "/", "MOD", "+", "-", "==", "<>", "<",
                                          ">", "<=", ">=", "AND", "BAND", "OR", "XOR", "BOR", "BXOR", ":"};
  static_assert(std::size(kText) == static_cast<std::size_t>(Op::count));
  return kText[static_cast<std::size_t>(op)];
}

Value apply_binary(Op op, const Value& a, const Value& b) {
  if (op == Op::compound) {
    if (kind_of(a) != Kind::trans || kind_of(b) != Kind::trans)
      raise(Message::illegal_value, "\":\" needs two transformations");
    motion::Location t = std::get<motion::Location>(a) * std::get<motion::Location>(b);
    // One Newton step towards the nearest rotation, R (3I - R^T R)/2: chains of 10^6 compounds
    // stay orthonormal to 1e-15 instead of drifting to 1e-10 (docs/stiff-cases.md); exact
    // rotations (identity, quarter turns) are left bit-identical.
    const Eigen::Matrix3d r = t.linear();
    t.linear() = 0.5 * r * (3.0 * Eigen::Matrix3d::Identity() - r.transpose() * r);
    return finite_location(t);
  }
  if (kind_of(a) == Kind::string || kind_of(b) == Kind::string) {
    const std::string& x = to_string_value(a);
    const std::string& y = to_string_value(b);
    if (op == Op::add) {
      if (x.size() + y.size() > kMaxStringLength) raise(Message::illegal_value, "string longer than 128 characters");
      return x + y;
    }
    if (!is_relational(op)) raise(Message::illegal_value, fmt::format("\"{}\" on strings", op_text(op)));
    return truth(compare(op, x, y));
  }
  return real_binary(op, to_real(a, op_text(op)), to_real(b, op_text(op)));
}

void raise_division_by_zero() { raise(Message::division_by_zero); }

}  // namespace asimov::interpreter
