// Stage 2: checks a parsed source (programs, blocks, labels, functions) and compiles each
// program into code (code.hpp) with names resolved to slots. Load-time problems are
// *Syntax error* diagnostics, all of them reported together.
#pragma once
#include "code.hpp"
#include "data_section.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "parser.hpp"
#include <string>
#include <unordered_map>
#include <vector>

namespace asimov::interpreter {

// Names resolved at load time. Owned by the interpreter and shared by all loads, so a slot
// stays valid when programs are replaced.
struct Symbols {
  std::vector<std::string> globals;                   // slot -> name
  std::unordered_map<std::string, int> global_slots;
  std::vector<std::string> programs;                  // slot -> name
  std::unordered_map<std::string, int> program_slots;

  int global(const std::string& name);                // interns
  int program(const std::string& name);               // interns
};

struct CheckResult {
  std::vector<Program> programs;                      // in file order
  std::vector<DataItem> data;                         // data sections, in file order
  std::size_t data_bytes = 0;                         // what their array elements will be charged
  std::vector<Diagnostic> errors;
  std::size_t unreported = 0;                         // errors past kMaxLoadErrors in one line, only counted
};

// `joint_count`: values of a precision point in a .LOCATIONS section.
CheckResult check_source(const ParsedSource& source, Symbols& symbols, int joint_count = 6);


// Precedence level of a binary operator (dialect §3; higher binds tighter).
int precedence(ast::Op op);

}  // namespace asimov::interpreter
