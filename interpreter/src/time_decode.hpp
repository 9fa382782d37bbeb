// $TIME and $DECODE (dialect §7): the string functions of V+ that need no interpreter state,
// as free functions the evaluator calls.
#pragma once
#include <ctime>
#include <optional>
#include <string>

namespace asimov::interpreter {

// $TIME(): `when` (the controller's clock) as "dd-MMM-yyyy hh:mm:ss". $TIME(date, time): the
// date and time packed as the controller's file system packs them (the DOS format: date =
// (year - 1980) * 512 + month * 32 + day, time = hour * 2048 + minute * 32 + seconds / 2); an
// omitted time is midnight. A value outside that format raises *Illegal value*.
std::string time_text(std::time_t when);
std::string time_text(double date, std::optional<double> time);

// $DECODE(var, breaks, mode): mode 0 takes the characters of `var` before the first one in
// `breaks` (all of them when none is), mode nonzero the run of characters in `breaks` at its
// start; what is taken is removed from `var` and returned.
std::string decode(std::string& var, const std::string& breaks, double mode);

}  // namespace asimov::interpreter
