// The controller's module format (dialect §1).
#include "module_format.hpp"

#include <cctype>

namespace asimov::interpreter {

namespace {

constexpr char kFormFeed = '\x0C';
constexpr char kCtrlZ = '\x1A';

bool blank(char c) { return c == ' ' || c == '\t' || c == kFormFeed; }
bool line_end(char c) { return c == '\n' || c == '\r'; }

// The Ctrl-Z at `z` ends the module: only blanks before it on its line, or `.END` and blanks.
bool ends_module(std::string_view text, std::size_t z) {
  std::size_t start = z;
  while (start > 0 && !line_end(text[start - 1])) --start;
  std::string before;
  for (std::size_t i = start; i < z; ++i)
    if (!blank(text[i])) before += static_cast<char>(std::tolower(static_cast<unsigned char>(text[i])));
  return before.empty() || before == ".end";
}

}  // namespace

std::string module_text(std::string_view source) {
  // A byte order mark is not text: an editor does not show it, so columns are counted after it.
  if (source.substr(0, 3) == "\xEF\xBB\xBF") source.remove_prefix(3);
  // Ctrl-Z ends the file, as in the CP/M and DOS text files the controller's tools wrote, where
  // it stands after the last line: at the start of a line, or right after the `.END` closing
  // the last program. What follows (the rest of the last sector) is not part of the module. A
  // Ctrl-Z inside a statement keeps its error.
  if (const auto z = source.find(kCtrlZ); z != std::string_view::npos && ends_module(source, z))
    source = source.substr(0, z);
  while (!source.empty() && source.back() == '\0') source.remove_suffix(1);

  std::string text(source);
  // Form feeds among the blanks that begin or end a line are page breaks: blanks. One between
  // other characters of a statement keeps its error.
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = start;
    while (end < text.size() && !line_end(text[end])) ++end;
    for (std::size_t i = start; i < end && blank(text[i]); ++i)
      if (text[i] == kFormFeed) text[i] = ' ';
    for (std::size_t i = end; i > start && blank(text[i - 1]); --i)
      if (text[i - 1] == kFormFeed) text[i - 1] = ' ';
    start = end + 1;
  }
  return text;
}

}  // namespace asimov::interpreter
