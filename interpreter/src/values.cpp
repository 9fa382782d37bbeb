#include "asimov/interpreter/values.hpp"

#include "errors.hpp"
#include "limits.hpp"

#include <fmt/format.h>

#include <cmath>

namespace asimov::interpreter {

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::real: return "real";
    case Kind::string: return "string";
    case Kind::trans: return "transformation";
    case Kind::ppoint: return "precision point";
  }
  return "?";
}

double to_real(const Value& v, const char* what) {
  if (const double* d = std::get_if<double>(&v)) return *d;
  raise(Message::illegal_value, fmt::format("{}, not a {}", what, kind_name(kind_of(v))));
}

const std::string& to_string_value(const Value& v) {
  if (const std::string* s = std::get_if<std::string>(&v)) return *s;
  raise(Message::illegal_value, fmt::format("string expected, not a {}", kind_name(kind_of(v))));
}

void raise_not_finite() { raise(Message::illegal_value, "result is not a finite number"); }

int to_index(double x) {
  const double r = std::round(x);  // halves away from zero
  if (!(r >= -2e9 && r <= 2e9)) raise(Message::illegal_value, fmt::format("{} is not an integer", x));
  return static_cast<int>(r);
}

std::string format_number(double x) {
  if (x == 0) return "0";  // also -0
  const double a = std::fabs(x);
  if (a < 1e15 && x == std::trunc(x)) return fmt::format("{:.0f}", x);
  if (a >= 1e-6 && a < 1e15) {
    std::string s = fmt::format("{:.6f}", x);
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    if (s == "-0") return "0";
    return s;
  }
  return fmt::format("{:.6g}", x);
}

}  // namespace asimov::interpreter
