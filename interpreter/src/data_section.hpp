// Lines of the .LOCATIONS, .REALS and .STRINGS sections (dialect §8, [ext]) turned into
// global values; the interpreter assigns them only when the whole load succeeds.
#pragma once
#include "ast.hpp"
#include "asimov/interpreter/values.hpp"
#include "asimov/core/result.hpp"
#include <string>

namespace asimov::interpreter {

struct Symbols;

// One global value from a data section.
struct DataItem {
  int slot = -1;                                      // global slot
  bool subscripted = false;
  Index index{0, 0, 0};
  Value value;
};

// `section` is Kw::dot_locations, dot_reals or dot_strings. A bad line: the error's message
// says why (the checker reports it at the line).
Result<DataItem> compile_data_line(const ast::DataLine& d, ast::Kw section, int joint_count, Symbols& symbols);

}  // namespace asimov::interpreter
