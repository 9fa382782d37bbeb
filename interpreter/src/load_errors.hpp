// Stage 2, the checker's errors: *Syntax error* diagnostics of one source, located at a file
// line and column and, inside a program, at its step; past kMaxLoadErrors in one line only
// counted (a statement of 10^6 operators may hold as many errors, each with a copy of its line).
#pragma once
#include "checker.hpp"

#include <string>

namespace asimov::interpreter {

class LoadErrors {
 public:
  // `in_program` and `program`: the checker's, read when an error is reported (its step).
  LoadErrors(const ParsedSource& src, CheckResult& out, const bool& in_program, const Program& program)
      : src_(src), out_(out), in_program_(in_program), program_(program) {}
  void start_line(int line, int column) { line_ = line, column_ = column, line_errors_ = 0; }
  int line() const { return line_; }        // the line being checked
  int column() const { return column_; }    // and the column of its statement
  void at(int line, int column, std::string detail);
  void here(std::string detail) { at(line_, column_, std::move(detail)); }
  // An error about `near` (a name): at the column of its first `near(` in the statement.
  void near(std::string detail, const std::string& near);
  // A block error that a syntax error in the same program may have caused (a block opener or
  // END the parser rejected) is not reported: the syntax error already is.
  void in_block(std::string detail) {
    if (!parse_error_between(program_.line, line_)) here(std::move(detail));
  }
  bool parse_error_between(int from, int to) const;

 private:
  void report(int line, int column, std::string detail);
  bool unreported();                        // counts an error of the current line; true past the limit
  int column_of(const std::string& name) const;

  const ParsedSource& src_;
  CheckResult& out_;
  const bool& in_program_;
  const Program& program_;
  int line_ = 0, column_ = 1;
  std::size_t line_errors_ = 0;             // errors of line_ so far
};

}  // namespace asimov::interpreter
