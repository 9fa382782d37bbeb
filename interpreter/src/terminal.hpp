// Terminal I/O of dialect §6: the text of TYPE and $ENCODE items, and the replies PROMPT reads.
#pragma once
#include "ast.hpp"
#include "asimov/interpreter/values.hpp"
#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace asimov::interpreter {

// The text of TYPE / $ENCODE items: `formats` has one entry per item, code 0 taking the next
// of `values` (already evaluated). `newline` is cleared by /S.
std::string format_items(const std::vector<ast::Format>& formats, const std::vector<Value>& values,
                         bool& newline);

// A PROMPT reply read as a real: optional blanks, an optional sign, a decimal number of
// dialect §1 (`12`, `-.5`, `1e-3`); anything else is nullopt.
std::optional<double> parse_reply_number(const std::string& text);

// Reads one line (without its CR LF); false at the end of input.
bool read_reply(std::istream& in, std::string& line);

}  // namespace asimov::interpreter
