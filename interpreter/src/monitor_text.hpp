// The monitor's text helpers (monitor.cpp): words, lists and the instruction words of DO.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace asimov::interpreter::monitor_text {

// Instruction words offered by completion after DO (dialect §5, §6): the do_ok words of
// instructions.def, upper case and sorted.
const std::vector<std::string>& do_words();
// Statements DO refuses: control flow and declarations (dialect §9), the no_do words.
bool not_for_do(const std::string& lower_word);
std::string trim(std::string_view s);
std::string lower(std::string s);
std::string upper(std::string s);
// Splits at commas outside brackets, parentheses and strings; each part trimmed.
std::vector<std::string> split_list(const std::string& s);

}  // namespace asimov::interpreter::monitor_text
