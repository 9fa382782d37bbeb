// The studio's message parser (app/serve/protocol.hpp): every WebSocket text message a browser,
// or anything else that got the token, sends to `asimov serve`. Outcome of bad input: an
// "*Invalid message*" error value, never a crash, an exception or deep recursion.
#include "app/serve/protocol.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov::serve;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto r = parse_request(text);
  if (r) {  // what passed holds within the bounds the rest of the server relies on
    if (r->text.size() > kMaxTextBytes || r->line.size() > kMaxLineBytes || r->file.size() > kMaxNameBytes ||
        r->main.size() > kMaxNameBytes || r->line.find_first_of("\r\n") != std::string::npos)
      __builtin_trap();
  } else if (r.error().message != "*Invalid message*") {
    __builtin_trap();
  }
  return 0;
}
