// The binary operators of dialect §3 on evaluated values: arithmetic with checked results,
// relational (numbers and strings), logical (TRUE = -1), bitwise on 32-bit integers, and the
// compound ':' of two transformations.
#pragma once
#include "interpreter/ast.hpp"
#include "interpreter/values.hpp"

namespace asimov::val {

inline double truth(bool b) { return b ? -1.0 : 0.0; }

// The operator as written, for messages.
const char* op_text(ast::Op op);

Value apply_binary(ast::Op op, const Value& a, const Value& b);

}  // namespace asimov::val
