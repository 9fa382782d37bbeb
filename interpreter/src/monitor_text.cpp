// The monitor's text helpers (monitor_text.hpp).
#include "monitor_text.hpp"

#include "instructions.hpp"

#include <algorithm>
#include <cctype>

namespace asimov::interpreter::monitor_text {

// Instruction words offered by completion after DO (dialect §5, §6): the do_ok words of
// instructions.def, upper case and sorted.
const std::vector<std::string>& do_words() {
  static const std::vector<std::string> out = [] {
    std::vector<std::string> w;
    for (const Word& word : words())
      if (word.flags & word_flag::do_ok) {
        std::string s(word.spelling);
        for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        w.push_back(std::move(s));
      }
    std::sort(w.begin(), w.end());
    return w;
  }();
  return out;
}

// Statements DO refuses: control flow and declarations (dialect §9), the no_do words.
bool not_for_do(const std::string& lower_word) {
  for (const Word& w : words())
    if ((w.flags & word_flag::no_do) && w.spelling == lower_word) return true;
  return false;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(b, e - b + 1));
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

// Splits at commas outside brackets, parentheses and strings; each part trimmed.
std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> parts;
  if (trim(s).empty()) return parts;
  int depth = 0;
  bool quoted = false;
  std::string cur;
  for (char c : s) {
    if (c == '"') quoted = !quoted;
    if (!quoted && (c == '(' || c == '[')) ++depth;
    if (!quoted && (c == ')' || c == ']')) --depth;
    if (c == ',' && depth == 0 && !quoted) {
      parts.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(trim(cur));
  return parts;
}

}  // namespace asimov::interpreter::monitor_text
