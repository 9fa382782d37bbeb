// The words of instructions.def as a table (code.cpp builds it): the parser's keyword tables and
// reserved words and the monitor's DO rules are read from here.
#pragma once
#include "ast.hpp"
#include <span>
#include <string_view>

namespace asimov::interpreter {

// The flags column of instructions.def (a namespace, so that the rows can name them bare).
namespace word_flag {
enum : unsigned {
  reserved = 1u << 0,     // never a variable name, not even where no instruction can stand (dialect §1)
  do_ok = 1u << 1,        // a monitor DO runs it; offered by completion after DO
  no_do = 1u << 2,        // control flow or a declaration: DO refuses it
  trailing = 1u << 3,     // ALWAYS, MONITOR, DO, THEN, OF after the arguments
  unit = 1u << 4,         // MMPS, IPS after SPEED's argument
  declaration = 1u << 5,  // AUTO, LOCAL, GLOBAL
  binding = 1u << 6,      // SET, DECOMPOSE, PARAMETER before `variable = expression`
};
}  // namespace word_flag

// One spelled word of instructions.def: every keyword, alias and reserved spelling.
struct Word {
  std::string_view spelling;       // lower case
  ast::Kw kw;                      // Kw::none for a spelling without a Kw
  unsigned flags;                  // word_flag bits
  bool instruction;                // starts an instruction of the generic rule (parser.cpp)
};
std::span<const Word> words();

}  // namespace asimov::interpreter
