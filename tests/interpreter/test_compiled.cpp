// The compiled real expressions (interpreter/realcode.*) and the dispatch loop's in-place
// stores against the generic evaluator: a function call makes an expression generic, so
// the same formula written both ways must print the same.
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;

TEST_CASE("compiled MOD and arithmetic agree with the generic path", "[evaluator][compiled]") {
  // ABS(0) forces the generic path; the numbers cover signs, zero results, non-integers and
  // operands outside 32 bits (the compiled MOD uses integers only inside).
  const std::string out = asimov::test::output_of_programs(R"(.PROGRAM main()
    z = 0
    FOR i = 1 TO 12
        x = i * 7 - 40
        y = 3
        IF i MOD 2 THEN
            y = -3
        END
        IF i == 5 THEN
            x = 5000000000
        END
        IF i == 6 THEN
            x = -7.5
        END
        IF i == 7 THEN
            y = 2.5
        END
        IF i == 8 THEN
            x = -6
        END
        a = x MOD y
        b = (x + ABS(z)) MOD y
        c = (x * 3 + i) / y - x
        d = (x * 3 + i + ABS(z)) / y - x
        TYPE a, b, c - d, a == b
    END
.END
)");
  std::size_t lines = 0, pos = 0;
  while ((pos = out.find('\n', pos)) != std::string::npos) ++lines, ++pos;
  CHECK(lines == 12);
  CHECK(out.find(" 0 -1\n") != std::string::npos);
  // Every line: a equals b, c - d is 0, and the comparison is TRUE.
  std::size_t start = 0;
  while (start < out.size()) {
    const std::size_t end = out.find('\n', start);
    const std::string line = out.substr(start, end - start);
    INFO(line);
    CHECK(line.size() >= 5);
    CHECK(line.substr(line.size() - 5) == " 0 -1");
    start = end + 1;
  }
  CHECK(asimov::test::output_of_programs(".PROGRAM main()\nx = -6\ny = 3\nTYPE x MOD y, -7 MOD 3, 7 MOD -3\n.END\n") == "0 -1 1\n");
}

TEST_CASE("compiled array indices round halves away from zero", "[evaluator][compiled]") {
  CHECK(asimov::test::output_of_programs(".PROGRAM main()\na[3] = 30\na[0] = 7\ni = 2.5\nj = -0.4\nTYPE a[i], a[j], a[2.5]\n"
                  "a[i] = 31\nTYPE a[3]\n.END\n") == "30 7 30\n31\n");
}

TEST_CASE("a reused frame starts with fresh parameters and AUTO variables", "[evaluator][compiled]") {
  // f runs from the same reused frame each time: its AUTO and by-value parameter must not
  // keep the previous call's values, and a by-reference argument is the caller's variable.
  CHECK(asimov::test::output_of_programs(R"(.PROGRAM main()
    FOR k = 1 TO 3
        CALL f(k * 10, r)
        TYPE r
    END
    CALL f(, r)
    TYPE r
.END
.PROGRAM f(x, out)
    AUTO t
    IF DEFINED(t) THEN
        out = -1
        RETURN
    END
    t = 1
    IF DEFINED(x) THEN
        out = x + t
    ELSE
        out = 0
    END
.END
)") == "11\n21\n31\n0\n");
}

TEST_CASE("compiled expressions fall back for strings and locations", "[evaluator][compiled]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\nSET t = TRANS(1,2,3)\nx = 1\nx = t + 1\n.END\n");
  REQUIRE(f.loaded);
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Illegal value*");
  CHECK(r.error.line == 4);
  InterpreterFixture g;
  const auto s = g.run(".PROGRAM main()\nFOR i = 1 TO 3\nx = i + q\nEND\n.END\n");
  REQUIRE(s.status == RunStatus::error);
  CHECK(s.error.message == "*Undefined value*");
  CHECK(s.error.detail == "q");
  CHECK(s.error.line == 3);
}
