#include "terminal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace asimov::interpreter {

std::string format_items(const std::vector<ast::Format>& formats, const std::vector<Value>& values,
                         bool& newline) {
  std::string text;
  bool after_number = false;  // the previous item was a number in default format
  ast::Format mode{'D', 0, 0};
  std::size_t next = 0;
  for (const ast::Format& item : formats) {
    switch (item.code) {
      case 0: {
        const Value& v = values[next++];
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

std::optional<double> parse_reply_number(const std::string& text) {
  std::size_t a = text.find_first_not_of(" \t");
  const std::size_t b = text.find_last_not_of(" \t");
  if (a == std::string::npos) return std::nullopt;
  const std::string s = text.substr(a, b - a + 1);
  // Only the characters of a decimal literal: strtod alone would take "inf", "nan" and hex.
  bool digit = false;
  for (char c : s) {
    if (std::isdigit(static_cast<unsigned char>(c))) digit = true;
    else if (!std::strchr("+-.eE", c)) return std::nullopt;
  }
  if (!digit) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

bool read_reply(std::istream& in, std::string& line) {
  if (!std::getline(in, line)) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

}  // namespace asimov::interpreter
