// Stage 1: source text -> one ast::Line per source line (Spirit X3; parser.cpp is the only
// X3 translation unit). Every line is parsed on its own, so a syntax error costs one line and
// all of a file's errors are reported together.
#pragma once
#include "limits.hpp"
#include "ast.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include <string>
#include <vector>

namespace asimov::interpreter {

struct ParsedSource {
  std::string file;
  std::vector<std::string> text;     // source lines without line ends; text[i] is line i+1
  std::vector<ast::Line> lines;      // same indexing; blank and comment lines hold nothing
  std::vector<Diagnostic> errors;    // syntax errors, in line order
  bool truncated = false;            // reading stopped at a file-wide limit (its error is in errors)
};

// max_file_operators: the file-wide limit (limits.hpp); smaller only in tests.
ParsedSource parse_source(const std::string& source, const std::string& file,
                          std::int64_t max_file_operators = kMaxFileOperators);

// Lower case, truncated to the 15 significant characters of dialect §1.
std::string normalize_name(const std::string& name);

}  // namespace asimov::interpreter
