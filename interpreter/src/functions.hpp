// Built-in functions of expressions (dialect §3, §4): the name table the checker resolves
// against, and their evaluation on already evaluated arguments.
#pragma once
#include "asimov/interpreter/values.hpp"
#include "asimov/motion/simulator.hpp"
#include <optional>
#include <string_view>
#include <vector>

namespace asimov::interpreter {

// ORDER: kFunctions in functions.cpp.
enum class Func : int {
  sin, cos, tan, asin, acos, atan2, sqrt, sqr, abs, int_, fract, sign, max, min, pi, true_,
  false_, random, bmask, here, dest, null, trans, ppoint, inverse, rx, ry, rz, dx, dy, dz,
  distance, shift, tool, base, len, chr, asc, val, defined, sig, timer, mid, last, frame,
  parameter, switch_, inrange, state, task, error, error_text, select, status, getc, iostat, tas, pdest,
  lngb_s, lngb, intb_s, intb, fltb_s, fltb,  // binary records: $LNGB LNGB $INTB INTB $FLTB FLTB
  speed, time_s, decode_s,  // SPEED(select), $TIME([date, time]), $DECODE(var, breaks, mode)
  priority,  // PRIORITY(): the program priority (dialect §7c)
  vplus,  // a V+ function that loads but is not simulated (dialect §13)
  count
};

struct FunctionInfo {
  std::string_view name;  // lower case, with '#' or '$' prefix when it returns one
  int min_args;
  int max_args;           // -1: any number
};

const FunctionInfo& function_info(Func f);
// Resolves a (normalized) function name; PPOINT without '#' is accepted [ext].
std::optional<Func> find_function(std::string_view name);

// Evaluates `f`. Absent arguments are std::nullopt (omitted, `TRANS(,,300)`).
// Raises *Illegal value* etc. through raise().
Value call_function(Func f, const std::vector<std::optional<Value>>& args,
                    const motion::Simulator& sim);

// Pose of a value used where a transformation is needed: a precision point goes through
// forward kinematics with the current BASE and TOOL (dialect §4).
motion::Location as_pose(const Value& v, const motion::Simulator& sim);

// A location result of an operation (`:`, INVERSE, SHIFT, FRAME, HERE, DEST): an overflow to
// infinity or NaN is an *Illegal value*, so no location ever holds one (docs/stiff-cases.md).
motion::Location finite_location(const motion::Location& t);
// TOOL, BASE: a transformation, else *Illegal value*.
motion::Location as_transformation(const Value& v);

}  // namespace asimov::interpreter
