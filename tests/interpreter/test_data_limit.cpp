// The memory limit of a program's data (issue 17, docs/limits.md): array elements, their
// strings and index tables are charged while they exist and given back when they go; past
// kMaxDataBytes a run stops with *Out of memory* and a load is refused, never std::bad_alloc.
#include "interpreter_fixture.hpp"

#include "interpreter/src/limits.hpp"

#include <catch2/catch.hpp>

using namespace asimov;
using interpreter::data_bytes;
using interpreter::Elements;
using interpreter::Index;
using interpreter::kMaxDataBytes;

TEST_CASE("array elements are charged while they exist", "[data_limit]") {
  const std::size_t before = data_bytes();
  {
    Elements a;
    a.set(Index{3, 0, 0}, 1.0);
    a.set(Index{1, 2, 3}, 2.0);
    CHECK(a.bytes() > 2 * sizeof(Elements::Map::value_type));
    CHECK(data_bytes() == before + a.bytes());
    a.set(Index{3, 0, 0}, 5.0);  // reassigned: no new charge
    CHECK(data_bytes() == before + a.bytes());
    Elements b = a;  // a copy is charged too
    CHECK(data_bytes() == before + 2 * a.bytes());
    CHECK(b.get(Index{3, 0, 0}) != nullptr);
    CHECK(std::get<double>(*b.get(Index{1, 2, 3})) == 2.0);
    Elements c = std::move(b);  // a move is not
    CHECK(b.bytes() == 0);
    CHECK(data_bytes() == before + 2 * a.bytes());
    c.clear();
    CHECK(data_bytes() == before + a.bytes());
    // A string element costs its largest string; a high index its table.
    Elements s;
    s.set(Index{0, 1, 0}, std::string("x"));
    CHECK(s.bytes() >= Elements::element_bytes(0.0) + interpreter::kMaxStringLength);
    Elements high;
    high.set(Index{65535, 0, 0}, 1.0);
    CHECK(high.bytes() >= 65536 * sizeof(void*));
  }
  CHECK(data_bytes() == before);
}

TEST_CASE("a program past the data limit stops with *Out of memory*", "[data_limit]") {
  test::InterpreterFixture f;
  const auto r = f.run(
      ".PROGRAM main()\n"
      "  FOR i = 0 TO 65535\n"
      "    FOR j = 0 TO 65535\n"
      "      a[i,j] = i\n"
      "    END\n"
      "  END\n"
      ".END\n");
  REQUIRE(f.loaded);
  CHECK(r.status == interpreter::RunStatus::error);
  CHECK(r.error.message == "*Out of memory*");
  CHECK(r.line == 4);
  CHECK(data_bytes() <= kMaxDataBytes);
  CHECK(data_bytes() > kMaxDataBytes - 4096);  // filled up to the limit, not refused early
}

TEST_CASE("data sections past the data limit are refused at load, at the line", "[data_limit]") {
  test::InterpreterFixture f;
  const std::size_t per = Elements::element_bytes(std::string("s"));
  const std::size_t lines = kMaxDataBytes / per + 10;
  std::string text = ".STRINGS\n";
  text.reserve(lines * 16);
  for (std::size_t k = 0; k < lines; ++k) text += "$s[" + std::to_string(k / 60000) + "," + std::to_string(k % 60000) + "] \"x\"\n";
  text += ".END\n";
  const std::size_t before = data_bytes();
  const auto d = f.load(text);
  REQUIRE(d.size() == 1);
  CHECK(d[0].message == "*Out of memory*");
  CHECK(d[0].detail == "the data sections exceed 256 MiB of program data");
  CHECK(d[0].line == static_cast<int>(kMaxDataBytes / per) + 2);  // the first element past the limit
  CHECK(data_bytes() == before);  // nothing loaded
}
