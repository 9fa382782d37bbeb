// Stage 2, the checker's errors (load_errors.hpp).
#include "load_errors.hpp"

#include "limits.hpp"

#include <cctype>
#include <cstring>

namespace asimov::interpreter {

void LoadErrors::at(int line, int column, std::string detail) {
  // Past what a LOAD reports (kMaxLoadErrors, the first ones of a line come first) errors are
  // only counted, so the report is the same and the memory linear.
  if (line == line_ && unreported()) return;
  report(line, column, std::move(detail));
}

void LoadErrors::near(std::string detail, const std::string& near) {
  // Counted before the column is looked for: column_of reads the whole line, and a line may
  // hold 10^6 unknown functions.
  if (!unreported()) report(line_, near.empty() ? column_ : column_of(near), std::move(detail));
}

void LoadErrors::report(int line, int column, std::string detail) {
  Diagnostic d;
  d.message = "*Syntax error*";
  d.detail = std::move(detail);
  d.file = src_.file;
  d.line = line;
  d.column = column;
  if (in_program_ && line > program_.line) {
    d.program = program_.name;
    d.step = line - program_.line;
  }
  d.source_line = src_.text[static_cast<std::size_t>(line - 1)];
  out_.errors.push_back(std::move(d));
}

bool LoadErrors::unreported() {
  if (line_errors_++ < kMaxLoadErrors) return false;
  ++out_.unreported;
  return true;
}

// The 1-based column of the first `name(` (case-insensitive, a whole word) of the current
// statement; the statement's column when it is not found.
int LoadErrors::column_of(const std::string& name) const {
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::string hay = lower(src_.text[static_cast<std::size_t>(line_ - 1)]), needle = lower(name);
  for (std::size_t at = hay.find(needle, static_cast<std::size_t>(column_ - 1)); at != std::string::npos;
       at = hay.find(needle, at + 1)) {
    std::size_t after = at + needle.size();
    while (after < hay.size() && (hay[after] == ' ' || hay[after] == '\t')) ++after;
    const char before = at == 0 ? ' ' : hay[at - 1];
    const bool starts = !(std::isalnum(static_cast<unsigned char>(before)) || std::strchr("._$#", before));
    if (starts && after < hay.size() && hay[after] == '(') return static_cast<int>(at) + 1;
  }
  return column_;
}

bool LoadErrors::parse_error_between(int from, int to) const {
  for (const Diagnostic& d : src_.errors)
    if (d.line > from && d.line < to) return true;
  return false;
}

}  // namespace asimov::interpreter
