#include "interpreter/errors.hpp"

#include <array>

namespace asimov::val {
namespace {

constexpr std::array<std::string_view, 8> kErrorMessages = {
    "*Syntax error*",
    "*Undefined program or variable name*",
    "*Undefined value*",
    "*Illegal value*",
    "*Division by zero*",
    "*Too many nested calls*",
    "*Too many statements*",  // our limit on executed statements (runaway programs)
    "*Motion error*",         // replaced by the simulator's own text
};
static_assert(kErrorMessages.size() == static_cast<std::size_t>(ErrorKind::count));

}  // namespace

std::string_view error_message(ErrorKind kind) {
  return kErrorMessages[static_cast<std::size_t>(kind)];
}

void raise(ErrorKind kind, std::string detail) {
  throw RuntimeError{std::string(error_message(kind)), std::move(detail)};
}

void raise_text(std::string message, std::string detail) {
  throw RuntimeError{std::move(message), std::move(detail)};
}

}  // namespace asimov::val
