// The V+ words asimov does not simulate (dialect §13, the inventory): every instruction,
// function, monitor command, switch and parameter of V+ that a program or session may use and
// asimov gives no meaning, with the reason. Such a word loads; an instruction or function stops
// the program when it runs (*Not supported in simulation*  KEYWORD: reason), or, marked
// no_effect, warns once and goes on. Words V+ does not have keep their syntax error.
#pragma once
#include <span>
#include <string_view>

namespace asimov::interpreter {

enum class WordKind : unsigned char { instruction, function, monitor, switch_, parameter };
enum class Support : unsigned char { no_effect, refused };

struct VplusWord {
  std::string_view name;    // upper case, with its $ or # prefix
  WordKind kind;
  Support support;
  std::string_view reason;  // why: "vision is not simulated" ...
};

std::span<const VplusWord> vplus_words();
// The entry for `name` (any case) of that kind; nullptr when asimov simulates it or V+ lacks it.
const VplusWord* vplus_word(std::string_view name, WordKind kind);
// "KEYWORD: reason", the detail of the refusal.
std::string vplus_refusal(const VplusWord& w);

}  // namespace asimov::interpreter
