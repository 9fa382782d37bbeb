// The controller's module format (dialect §1).
#include "module_format.hpp"

namespace asimov::interpreter {

namespace {

constexpr char kFormFeed = '\x0C';
constexpr char kCtrlZ = '\x1A';

bool blank(char c) { return c == ' ' || c == '\t' || c == kFormFeed; }
bool line_end(char c) { return c == '\n' || c == '\r'; }

}  // namespace

std::string module_text(std::string_view source) {
  // A byte order mark is not text: an editor does not show it, so columns are counted after it.
  if (source.substr(0, 3) == "\xEF\xBB\xBF") source.remove_prefix(3);
  // Ctrl-Z ends the file, as in the CP/M and DOS text files the controller's tools wrote; what
  // follows (the rest of the last sector) is not part of the module.
  if (const auto z = source.find(kCtrlZ); z != std::string_view::npos) source = source.substr(0, z);
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
