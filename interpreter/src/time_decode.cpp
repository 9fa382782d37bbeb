// $TIME and $DECODE (dialect §7).
#include "time_decode.hpp"

#include "errors.hpp"
#include "asimov/interpreter/values.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

namespace asimov::interpreter {
namespace {

constexpr std::array<const char*, 12> kMonths = {"JAN", "FEB", "MAR", "APR", "MAY", "JUN",
                                                 "JUL", "AUG", "SEP", "OCT", "NOV", "DEC"};

std::string format_time(int year, int month, int day, int hour, int minute, int second) {
  return fmt::format("{:02}-{}-{:04} {:02}:{:02}:{:02}", day, kMonths[static_cast<std::size_t>(month - 1)], year, hour,
                     minute, second);
}

// The packed value: an integer 0..65535; anything else is no packed date or time.
unsigned packed(double v, const char* what) {
  if (!(v >= 0 && v <= 65535) || v != std::floor(v))
    raise(Message::illegal_value, fmt::format("$TIME: {} {} is not a packed {}", what, format_number(v), what));
  return static_cast<unsigned>(v);
}

}  // namespace

std::string time_text(std::time_t when) {
  std::tm t{};
  localtime_r(&when, &t);
  return format_time(t.tm_year + 1900, t.tm_mon + 1, t.tm_mday, t.tm_hour, t.tm_min, t.tm_sec);
}

std::string time_text(double date, std::optional<double> time) {
  const unsigned d = packed(date, "date"), t = time ? packed(*time, "time") : 0;
  const int month = static_cast<int>((d >> 5) & 15), day = static_cast<int>(d & 31);
  const int hour = static_cast<int>(t >> 11), minute = static_cast<int>((t >> 5) & 63), second = static_cast<int>(t & 31) * 2;
  if (month < 1 || month > 12 || day < 1)
    raise(Message::illegal_value, fmt::format("$TIME: date {} is not a packed date", format_number(date)));
  if (hour > 23 || minute > 59 || second > 59)
    raise(Message::illegal_value, fmt::format("$TIME: time {} is not a packed time", format_number(*time)));
  return format_time(1980 + static_cast<int>(d >> 9), month, day, hour, minute, second);
}

std::string decode(std::string& var, const std::string& breaks, double mode) {
  const std::size_t end = mode == 0 ? var.find_first_of(breaks) : var.find_first_not_of(breaks);
  const std::size_t n = end == std::string::npos ? var.size() : end;
  std::string taken = var.substr(0, n);
  var.erase(0, n);
  return taken;
}

}  // namespace asimov::interpreter
