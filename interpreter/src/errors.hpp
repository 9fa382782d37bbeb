// The VAL messages of dialect §10 (Message, their texts) and the one raise point. raise() is
// for the problems found while evaluating a statement (*Illegal value*, *Undefined value*, ...,
// often deep in an expression): it throws a Fault, which only Evaluator::protected_run catches
// (docs/design.md "Errors"). What ends a run otherwise
// (contact, PAUSE, HALT, Ctrl-C, a motion error, a limit) is a RunStatus returned through the
// run loop. errors.cpp also formats reports (format_diagnostic, declared in interpreter.hpp).
#pragma once
#include <string>
#include <string_view>

namespace asimov::interpreter {

// ORDER: kMessageTexts in errors.cpp.
enum class Message : int {
  syntax, undefined_name, undefined_value, illegal_value, division_by_zero, too_many_calls,
  too_many_statements, motion, not_supported, interrupted, wait_limit, out_of_memory, not_executable, count
};

std::string_view message_text(Message kind);

// A VAL message that stops the run: what raise() throws, and what a status return of the run
// loop leaves in Evaluator::fault_ for the report.
struct Fault {
  Message kind = Message::motion;  // motion: `message` is the simulator's own text
  std::string message;             // "*Illegal value*", or the simulator's text for motion errors
  std::string detail;
};

// Codes for ERROR() and $ERROR() (dialect §7): asimov's own numbers in V+'s error range
// (-300 ... -1300) for the messages a run can stop with (the simulator's too). 0: no error; a
// message without a code of its own gets -1300.
int error_code(std::string_view message);
// The message of a code: "" for 0, "*Unknown error code*" for a code asimov never gives.
std::string error_text(int code);

Fault fault(Message kind, std::string detail = {});
[[noreturn]] void raise(Message kind, std::string detail = {});
// A VAL error with its own text (the cell's devices and parts: "*Nothing in the gripper*").
[[noreturn]] void raise_text(std::string message, std::string detail);

}  // namespace asimov::interpreter
