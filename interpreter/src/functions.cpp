#include "functions.hpp"

#include "errors.hpp"
#include "vplus_words.hpp"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>

namespace asimov::interpreter {
namespace {

constexpr std::array<FunctionInfo, 69> kFunctions = {{
    {"sin", 1, 1},      {"cos", 1, 1},      {"tan", 1, 1},     {"asin", 1, 1},
    {"acos", 1, 1},     {"atan2", 2, 2},    {"sqrt", 1, 1},    {"sqr", 1, 1},
    {"abs", 1, 1},      {"int", 1, 1},      {"fract", 1, 1},   {"sign", 1, 1},
    {"max", 1, -1},     {"min", 1, -1},     {"pi", 0, 0},      {"true", 0, 0},
    {"false", 0, 0},    {"random", 0, 0},   {"bmask", 1, -1},  {"here", 0, 0},
    {"dest", 0, 0},     {"null", 0, 0},     {"trans", 0, 6},   {"#ppoint", 0, robots::kMaxJoints},
    {"inverse", 1, 1},  {"rx", 1, 1},       {"ry", 1, 1},      {"rz", 1, 1},
    {"dx", 1, 1},       {"dy", 1, 1},       {"dz", 1, 1},      {"distance", 2, 2},
    {"shift", 4, 4},    {"tool", 0, 0},     {"base", 0, 0},    {"len", 1, 1},
    {"$chr", 1, 1},     {"asc", 1, 2},      {"val", 1, 1},     {"defined", 1, 1},
    {"sig", 1, -1},     {"timer", 1, 1},    {"$mid", 3, 3},    {"last", 1, 1},
    {"frame", 4, 4},    {"parameter", 1, 1}, {"switch", 1, 1},  {"inrange", 1, 1},
    {"state", 1, 1},    {"task", 0, 2},     {"error", 1, 2},   {"$error", 1, 1},
    {"select", 1, 1},   {"status", 1, 1},   {"getc", 1, 2},    {"iostat", 1, 2},
    {"tas", 2, 2},      {"#pdest", 0, 0},   {"$lngb", 1, 1},   {"lngb", 1, 2},
    {"$intb", 1, 1},    {"intb", 1, 2},     {"$fltb", 1, 1},   {"fltb", 1, 2},
    {"speed", 1, 1},    {"$time", 0, 2},    {"$decode", 3, 3},  {"priority", 0, 0},
    {"", 0, -1},
}};
static_assert(kFunctions.size() == static_cast<std::size_t>(Func::count));


constexpr double kDeg = std::numbers::pi / 180.0;

double real_arg(const std::vector<std::optional<Value>>& args, std::size_t i) {
  if (i >= args.size() || !args[i]) return 0;  // omitted numeric arguments are 0
  return to_real(*args[i]);
}

const Value& arg(const std::vector<std::optional<Value>>& args, std::size_t i) {
  if (i >= args.size() || !args[i]) raise(Message::undefined_value, "missing argument");
  return *args[i];
}

motion::Location trans_only(const Value& v) {
  if (const auto* t = std::get_if<motion::Location>(&v)) return *t;
  raise(Message::illegal_value, fmt::format("transformation expected, not a {}", kind_name(kind_of(v))));
}

motion::Location rotation(int axis, double deg) {
  motion::Location t = motion::Location::Identity();
  t.linear() = Eigen::AngleAxisd(deg * kDeg, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
  return t;
}

// Binary records (V+ $LNGB / LNGB, $INTB / INTB, $FLTB / FLTB): big-endian bytes, the most
// significant first. A value is rounded to an integer of the 32-bit range; $INTB packs its low
// 16 bits as $LNGB packs 32 [assumption: the same range check].
std::uint32_t bits32(double v, const char* name) {
  const double r = std::round(v);
  if (!(r >= -2147483648.0 && r <= 2147483647.0))
    raise(Message::illegal_value, fmt::format("{}({}) is outside -^H80000000..^H7FFFFFFF", name, format_number(v)));
  return static_cast<std::uint32_t>(static_cast<std::int32_t>(r));
}

std::string pack_bytes(std::uint32_t bits, int bytes) {
  std::string s;
  for (int k = bytes - 1; k >= 0; --k) s += static_cast<char>((bits >> (8 * k)) & 0xFF);
  return s;
}

// The `bytes` bytes of $s from position first (omitted, 0 or 1: the first); beyond the end is
// an error, as on the controller.
std::uint32_t unpack_bytes(const std::vector<std::optional<Value>>& args, int bytes, const char* name) {
  const std::string& s = to_string_value(arg(args, 0));
  const int first = args.size() > 1 && args[1] ? std::max(1, to_index(to_real(*args[1]))) : 1;
  if (static_cast<std::size_t>(first - 1 + bytes) > s.size())
    raise(Message::illegal_value, fmt::format("{}: {} bytes from position {} of a {}-byte string", name, bytes, first, s.size()));
  std::uint32_t bits = 0;
  for (int k = 0; k < bytes; ++k) bits = (bits << 8) | static_cast<unsigned char>(s[static_cast<std::size_t>(first - 1 + k)]);
  return bits;
}

double snap(double x) { return std::fabs(x) < 1e-15 ? 0.0 : x; }  // sin(180) -> 0, no -0 noise

}  // namespace

const FunctionInfo& function_info(Func f) { return kFunctions[static_cast<std::size_t>(f)]; }

std::optional<Func> find_function(std::string_view name) {
  if (name == "ppoint") name = "#ppoint";  // [ext]
  for (std::size_t i = 0; i < kFunctions.size(); ++i)
    if (kFunctions[i].name == name) return static_cast<Func>(i);
  // Dialect §13: a V+ function asimov does not simulate loads, and stops the program when it runs.
  if (vplus_word(name, WordKind::function)) return Func::vplus;
  return std::nullopt;
}

motion::Location as_pose(const Value& v, const motion::Simulator& sim) {
  if (const auto* j = std::get_if<robots::JointVector>(&v))
    return sim.settings().base * robots::flange_pose(sim.robot(), *j) * sim.settings().tool;
  return trans_only(v);
}

motion::Location finite_location(const motion::Location& t) {
  if (!t.matrix().allFinite()) raise_not_finite();
  return t;
}

motion::Location as_transformation(const Value& v) {
  if (const auto* t = std::get_if<motion::Location>(&v)) return *t;
  raise(Message::illegal_value, fmt::format("transformation expected, not a {}", kind_name(kind_of(v))));
}

Value call_function(Func f, const std::vector<std::optional<Value>>& args,
                    const motion::Simulator& sim) {
  auto x = [&](std::size_t i) { return real_arg(args, i); };
  switch (f) {
    case Func::sin: return snap(std::sin(x(0) * kDeg));
    case Func::cos: return snap(std::cos(x(0) * kDeg));
    case Func::tan: return finite(snap(std::tan(x(0) * kDeg)));
    case Func::asin:
    case Func::acos: {
      const double v = x(0);
      if (std::fabs(v) > 1) raise(Message::illegal_value, fmt::format("{} outside [-1, 1]", v));
      return (f == Func::asin ? std::asin(v) : std::acos(v)) / kDeg;
    }
    case Func::atan2: {
      double a = std::atan2(x(0), x(1)) / kDeg;
      if (a == -180.0) a = 180.0;
      return a + 0.0;
    }
    case Func::sqrt: {
      const double v = x(0);
      if (v < 0) raise(Message::illegal_value, fmt::format("SQRT({})", v));
      return std::sqrt(v);
    }
    case Func::sqr: return finite(x(0) * x(0));
    case Func::abs: return std::fabs(x(0));
    case Func::int_: return std::trunc(x(0));
    case Func::fract: return x(0) - std::trunc(x(0));
    case Func::sign: return x(0) < 0 ? -1.0 : 1.0;
    case Func::max:
    case Func::min: {
      double r = to_real(arg(args, 0));
      for (std::size_t i = 1; i < args.size(); ++i) {
        const double v = to_real(arg(args, i));
        r = f == Func::max ? std::max(r, v) : std::min(r, v);
      }
      return r;
    }
    case Func::pi: return std::numbers::pi;
    case Func::true_: return -1.0;
    case Func::false_: return 0.0;
    case Func::random: {
      static std::mt19937_64 engine(20260101);  // fixed seed at start-up [assumption]
      return std::uniform_real_distribution<double>(0.0, 1.0)(engine);
    }
    case Func::bmask: {
      double r = 0;
      for (std::size_t i = 0; i < args.size(); ++i) {
        const int b = to_index(to_real(arg(args, i)));
        if (b < 1 || b > 32) raise(Message::illegal_value, fmt::format("bit {} not in 1..32", b));
        r = static_cast<double>(static_cast<std::int64_t>(r) | (std::int64_t{1} << (b - 1)));
      }
      return r;
    }
    case Func::here: return finite_location(sim.here());
    case Func::dest: return finite_location(sim.dest());
    case Func::null: return motion::Location(motion::Location::Identity());
    case Func::tool: return sim.settings().tool;
    case Func::base: return sim.settings().base;
    case Func::trans: return motion::trans(x(0), x(1), x(2), x(3), x(4), x(5));
    case Func::pdest: return sim.planned_joints();  // the pending motion's end (tasks: Evaluator::function)
    case Func::ppoint: {
      const int n = sim.robot().joint_count();
      if (static_cast<int>(args.size()) > n)
        raise(Message::illegal_value, fmt::format("{} joint values for {} joints", args.size(), n));
      robots::JointVector j(n);
      for (int i = 0; i < n; ++i) j[i] = x(static_cast<std::size_t>(i));
      return j;
    }
    case Func::inverse: return finite_location(motion::Location(trans_only(arg(args, 0)).inverse()));
    case Func::rx: return rotation(0, x(0));
    case Func::ry: return rotation(1, x(0));
    case Func::rz: return rotation(2, x(0));
    case Func::dx: return trans_only(arg(args, 0)).translation().x();
    case Func::dy: return trans_only(arg(args, 0)).translation().y();
    case Func::dz: return trans_only(arg(args, 0)).translation().z();
    case Func::distance:  // stableNorm: no overflow of the squares below DBL_MAX
      return finite((as_pose(arg(args, 0), sim).translation() - as_pose(arg(args, 1), sim).translation()).stableNorm());
    case Func::shift: {
      motion::Location t = trans_only(arg(args, 0));
      t.translation() += Eigen::Vector3d(x(1), x(2), x(3));
      return finite_location(t);
    }
    case Func::len: return static_cast<double>(to_string_value(arg(args, 0)).size());
    case Func::chr: {  // a string holds any byte 0..255 (binary records: $LNGB, GETC)
      const int c = to_index(x(0));
      if (c < 0 || c > 255) raise(Message::illegal_value, fmt::format("$CHR({})", c));
      return std::string(1, static_cast<char>(c));
    }
    case Func::lngb_s: return pack_bytes(bits32(x(0), "$LNGB"), 4);
    case Func::intb_s: return pack_bytes(bits32(x(0), "$INTB"), 2);
    case Func::lngb: return static_cast<double>(static_cast<std::int32_t>(unpack_bytes(args, 4, "LNGB")));
    case Func::intb: return static_cast<double>(static_cast<std::int16_t>(unpack_bytes(args, 2, "INTB")));
    case Func::fltb_s: {  // IEEE single precision, rounded to nearest
      const double v = x(0);
      if (!(std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max())))
        raise(Message::illegal_value, fmt::format("$FLTB({}) is outside the single-precision range", format_number(v)));
      return pack_bytes(std::bit_cast<std::uint32_t>(static_cast<float>(v)), 4);
    }
    case Func::fltb: {  // exponent 0: zero, 255: overflow (the controller's rule)
      const std::uint32_t bits = unpack_bytes(args, 4, "FLTB");
      const std::uint32_t exponent = (bits >> 23) & 0xFF;
      if (exponent == 0xFF) raise(Message::illegal_value, "FLTB: exponent 255 (infinity or not a number)");
      if (exponent == 0) return 0.0;
      return static_cast<double>(std::bit_cast<float>(bits));
    }
    case Func::asc: {
      const std::string& s = to_string_value(arg(args, 0));
      const int i = args.size() > 1 && args[1] ? to_index(x(1)) : 1;
      if (i < 1 || i > static_cast<int>(s.size())) return -1.0;
      return static_cast<double>(static_cast<unsigned char>(s[static_cast<std::size_t>(i - 1)]));
    }
    case Func::val: {
      const std::string& s = to_string_value(arg(args, 0));
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(s, &used);
      } catch (...) {
        used = 0;
      }
      if (used == 0 || !std::isfinite(v)) raise(Message::illegal_value, fmt::format("VAL(\"{}\")", s));
      return v;
    }
    case Func::mid: {  // $MID($s, i, n): 1-based
      const std::string& s = to_string_value(arg(args, 0));
      const int i = to_index(x(1)), n = to_index(x(2));
      if (i < 1 || n < 0) raise(Message::illegal_value, fmt::format("$MID(, {}, {})", i, n));
      if (static_cast<std::size_t>(i) > s.size()) return std::string();
      return s.substr(static_cast<std::size_t>(i - 1), static_cast<std::size_t>(n));
    }
    case Func::frame: {
      const Eigen::Vector3d a = as_pose(arg(args, 0), sim).translation();
      const Eigen::Vector3d b = as_pose(arg(args, 1), sim).translation();
      const Eigen::Vector3d c = as_pose(arg(args, 2), sim).translation();
      // Differences of finite points may overflow; stableNorm/stableNormalized keep large
      // (>1e154) vectors from squaring to infinity and leaving a zero "rotation".
      const Eigen::Vector3d x_axis = b - a;
      if (!x_axis.allFinite() || !(c - a).allFinite()) raise_not_finite();
      if (x_axis.stableNorm() < 1e-9) raise(Message::illegal_value, "FRAME: a and b coincide");
      const Eigen::Vector3d x_hat = x_axis.stableNormalized();
      const Eigen::Vector3d y_part = (c - a) - (c - a).dot(x_hat) * x_hat;
      if (!y_part.allFinite()) raise_not_finite();
      if (y_part.stableNorm() < 1e-9) raise(Message::illegal_value, "FRAME: c is on the line a-b");
      const Eigen::Vector3d y_hat = y_part.stableNormalized();
      motion::Location t = motion::Location::Identity();
      t.linear().col(0) = x_hat;
      t.linear().col(1) = y_hat;
      t.linear().col(2) = x_hat.cross(y_hat);
      t.translation() = as_pose(arg(args, 3), sim).translation();
      return finite_location(t);
    }
    case Func::inrange: return static_cast<double>(sim.inrange(as_pose(arg(args, 0), sim)));
    case Func::defined:  // DEFINED, SIG, TIMER, LAST...: the evaluator (they need its state)
    case Func::parameter:
    case Func::switch_:
    case Func::vplus:
    case Func::last:
    case Func::sig:
    case Func::timer:
    case Func::state:
    case Func::task:
    case Func::error:
    case Func::error_text:
    case Func::select:
    case Func::status:
    case Func::getc:
    case Func::iostat:
    case Func::tas:
    case Func::speed:
    case Func::time_s:
    case Func::decode_s:
    case Func::priority:
    case Func::count: break;
  }
  raise(Message::illegal_value, "bad function");
}

}  // namespace asimov::interpreter
