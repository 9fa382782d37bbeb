// Stage 2, expressions: turns the parser's flat operand/operator lists into Node trees
// (precedence table of dialect §3), resolves variable names to slots (parameters and AUTO,
// then LOCAL, then GLOBAL) and function names to Func, and reports the visible string/number
// mixes. Used by the checker for every expression of a program.
#pragma once
#include "checker.hpp"
#include "code.hpp"
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

namespace asimov::interpreter {

class ExpressionCompiler {
 public:
  // `program`: the program being compiled (its parameters, AUTO and LOCAL names); `error`
  // reports a load-time problem at the current statement, at the first `near(` of its text
  // when `near` is not empty (a function name), else where the statement starts.
  using ErrorSink = std::function<void(std::string detail, const std::string& near)>;
  ExpressionCompiler(Symbols& symbols, const Program& program, ErrorSink error)
      : symbols_(symbols), prog_(program), error_(std::move(error)) {}

  Node expression(const ast::Expr& e);
  // `whole_array_ok`: a[] is allowed (a CALL argument, LAST). `shape_use`: the reference says
  // whether the name is a scalar or an array (false: DEFINED, a by-reference CALL argument).
  Node variable(const ast::VarRef& v, bool whole_array_ok, bool shape_use = true);
  // A program's names are each a scalar or an array (dialect §2): the first use or declaration
  // of a name decides, a later one of the other shape is an error. new_scope() forgets them.
  void note_shape(const std::string& name, bool array);
  void new_scope() { shapes_.clear(); }
  // TYPE and $ENCODE items: a format (code in upper case) or an expression (code 0).
  void format_items(const ast::TypeStmt& t, std::vector<ast::Format>& formats, std::vector<Node>& values);

  // The variable when `e` is just a variable (by-reference argument, HERE target ...).
  static const ast::VarRef* plain_variable(const ast::Expr& e, bool subscript_ok);
  // A switch or parameter name (CP, HAND.TIME, ...) as an upper-case string node.
  static Node setting_name(const ast::VarRef& v);

 private:
  Node climb(Node lhs, const std::vector<ast::Operation>& rest, std::size_t& pos, int min_prec);
  Node operand(const ast::Operand& o);
  Node function(const ast::Call& call);
  void error(std::string detail, const std::string& near = {}) { error_(std::move(detail), near); }

  Symbols& symbols_;
  const Program& prog_;
  ErrorSink error_;
  std::unordered_map<std::string, bool> shapes_;  // name -> used as an array, in this program
  int depth_ = 0;  // nesting of expression(): only whole expressions are marked and compiled
};

}  // namespace asimov::interpreter
