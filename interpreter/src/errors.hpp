// Runtime error kinds and their VAL texts (dialect §10), and the one raise point. The
// evaluator's run loop is the one protected boundary that turns a raise into a Diagnostic.
// errors.cpp also formats reports (format_diagnostic, declared in interpreter.hpp).
#pragma once
#include <string>
#include <string_view>

namespace asimov::interpreter {

// ORDER: kErrorMessages in errors.cpp.
enum class ErrorKind : int {
  syntax, undefined_name, undefined_value, illegal_value, division_by_zero, too_many_calls,
  too_many_statements, motion, not_supported, interrupted, wait_limit, count
};

std::string_view error_message(ErrorKind kind);

// What raise() throws; caught only by Evaluator::run.
struct RuntimeError {
  ErrorKind kind = ErrorKind::motion;  // motion: raise_text (the simulator's own text)
  std::string message;  // "*Illegal value*", or the simulator's text for motion errors
  std::string detail;
};

[[noreturn]] void raise(ErrorKind kind, std::string detail = {});
[[noreturn]] void raise_text(std::string message, std::string detail);

}  // namespace asimov::interpreter
