// Runtime values and variables (dialect §2) and the default number format (§3).
#pragma once
#include "motion/location.hpp"
#include "robots/robot.hpp"
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <variant>

namespace asimov::val {

enum class Kind : unsigned char { real, string, trans, ppoint };

// A real, a string, a transformation or a precision point (display joint values).
using Value = std::variant<double, std::string, motion::Location, robots::JointVector>;

inline Kind kind_of(const Value& v) { return static_cast<Kind>(v.index()); }
const char* kind_name(Kind kind);

// The value as a real; anything else is an *Illegal value* naming `what`.
double to_real(const Value& v, const char* what = "number expected");
const std::string& to_string_value(const Value& v);
// The checked result of arithmetic: non-finite is an *Illegal value*.
[[noreturn]] void raise_not_finite();
inline double finite(double x) {
  if (!std::isfinite(x)) raise_not_finite();
  return x;
}
// Integer contexts (indices, counts): nearest, halves away from zero.
int to_index(double x);

using Index = std::array<int, 3>;

// One named variable: a scalar or an array, never both. Elements grow on assignment.
struct Variable {
  std::optional<Value> scalar;            // scalar value, when assigned
  std::map<Index, Value> elements;        // array elements, when assigned
  bool is_array() const { return !elements.empty(); }
};

// Default number format of TYPE (dialect §3).
std::string format_number(double x);

}  // namespace asimov::val
