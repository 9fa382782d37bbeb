// Running programs without motion: arithmetic, variables, control flow, CALL, TYPE, errors.
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;

namespace {

// Runs `body` as the program `main` and returns its TYPE output.
std::string output_of(const std::string& body) {
  return asimov::test::output_of_programs(".PROGRAM main()\n" + body + "\n.END\n");
}

}  // namespace

TEST_CASE("arithmetic and precedence", "[evaluator]") {
  CHECK(output_of("TYPE -2 * -3") == "6\n");
  CHECK(output_of("TYPE 1 + 2 * 3") == "7\n");
  CHECK(output_of("TYPE (1 + 2) * 3") == "9\n");
  CHECK(output_of("TYPE 7 MOD 3, -7 MOD 3") == "1 -1\n");
  CHECK(output_of("TYPE 10 - 4 - 3") == "3\n");
  CHECK(output_of("TYPE 2 < 3, 3 < 2") == "-1 0\n");
  CHECK(output_of("TYPE 1 <> 2, 2 =< 2, 2 => 3") == "-1 -1 0\n");
  CHECK(output_of("a = 0\nb = 0\nTYPE NOT a == b") == "0\n");    // (NOT a) == b: -1 == 0
  CHECK(output_of("a = 0\nb = 0\nTYPE NOT (a == b)") == "0\n");
  CHECK(output_of("a = 5\nb = 0\nTYPE NOT a == b") == "-1\n");   // (NOT 5) == 0
  CHECK(output_of("TYPE 1 OR 0 AND 0") == "-1\n");                // AND binds tighter
  CHECK(output_of("TYPE 1 + 1 == 2 AND 3 > 2") == "-1\n");
  CHECK(output_of("TYPE TRUE, FALSE") == "-1 0\n");
  CHECK(output_of("TYPE ^B101000 BOR ^B100001, ^B101000 OR ^B100001") == "41 -1\n");
  CHECK(output_of("TYPE ^HFF, ^17, 'A") == "255 15 65\n");
  CHECK(output_of("TYPE 1 XOR 1, 0 XOR 1") == "0 -1\n");
}

TEST_CASE("numeric functions", "[evaluator]") {
  CHECK(output_of("TYPE SIN(30), COS(60), TAN(45)") == "0.5 0.5 1\n");
  CHECK(output_of("TYPE ATAN2(1, 1), ATAN2(0, -1), ATAN2(0, 0)") == "45 180 0\n");
  CHECK(output_of("TYPE SQRT(16), ABS(-3), INT(-2.7), INT(2.7)") == "4 3 -2 2\n");
  CHECK(output_of("TYPE MIN(3, 1, 2), MAX(3, 1, 2), MAX(4)") == "1 3 4\n");
  CHECK(output_of("TYPE SQR(3), SIGN(0), SIGN(-2), FRACT(2.5)") == "9 1 -1 0.5\n");
}

TEST_CASE("TYPE number format and spacing", "[evaluator][type]") {
  CHECK(output_of("TYPE 1, 2") == "1 2\n");
  CHECK(output_of("TYPE \"x=\", 3") == "x=3\n");
  CHECK(output_of("TYPE \"x=\", 3, \" y=\", 4") == "x=3 y=4\n");
  CHECK(output_of("TYPE 1/3") == "0.333333\n");
  CHECK(output_of("TYPE 0.00000015") == "1.5e-07\n");
  CHECK(output_of("TYPE 1e15") == "1e+15\n");
  CHECK(output_of("TYPE 123456789012345") == "123456789012345\n");
  CHECK(output_of("TYPE -0.0, -1 * 0") == "0 0\n");
  CHECK(output_of("TYPE 2.50") == "2.5\n");
  CHECK(output_of("TYPE /F8.3, 3.14159, /D, 2") == "   3.1422\n");
  CHECK(output_of("TYPE /I4, 7.6") == "   8\n");
  CHECK(output_of("TYPE \"a\", /X3, \"b\"") == "a   b\n");
  CHECK(output_of("TYPE \"a\", /S\nTYPE \"b\"") == "ab\n");
  CHECK(output_of("TYPE \"a\", /C2, \"b\"") == "a\n\nb\n");
  CHECK(output_of("TYPE") == "\n");
  CHECK(output_of("TYPE \"Hello; not a comment\" ; a comment") == "Hello; not a comment\n");
}

TEST_CASE("strings", "[evaluator]") {
  CHECK(output_of("$a = \"ab\"\n$b = $a + \"CD\"\nTYPE $b, LEN($b)") == "abCD4\n");
  CHECK(output_of("TYPE \"a\" < \"b\", \"a\" == \"a\"") == "-1 -1\n");
  CHECK(output_of("TYPE $CHR(65), ASC(\"A\"), VAL(\"2.5\")") == "A65 2.5\n");
}

TEST_CASE("any letter case", "[evaluator]") {
  CHECK(output_of("Total = 2\ntype TOTAL * total\nIf total == 2 Then\nTYPE \"yes\"\nend") == "4\nyes\n");
}

TEST_CASE("FOR leaves the variable one step past the limit", "[evaluator][control]") {
  CHECK(output_of("FOR i = 1 TO 5\nTYPE i, /S\nEND\nTYPE \"\"\nTYPE i") == "12345\n6\n");
  CHECK(output_of("FOR i = 10 TO 1 STEP -3\nTYPE i\nEND\nTYPE i") == "10\n7\n4\n1\n-2\n");
  CHECK(output_of("FOR i = 5 TO 1\nTYPE \"never\"\nEND\nTYPE i") == "5\n");
  CHECK(output_of("n = 0\nFOR i = 1 TO 3\nFOR j = 1 TO 2\nn = n + 1\nEND\nEND\nTYPE n, i, j") == "6 4 3\n");
}

TEST_CASE("IF, ELSE, WHILE, DO UNTIL, EXIT, NEXT", "[evaluator][control]") {
  CHECK(output_of("x = 3\nIF x > 2 THEN\nTYPE \"big\"\nELSE\nTYPE \"small\"\nEND") == "big\n");
  CHECK(output_of("x = 1\nIF x > 2 THEN\nTYPE \"big\"\nELSE\nTYPE \"small\"\nEND") == "small\n");
  CHECK(output_of("x = 1\nIF x > 2 THEN\nTYPE \"big\"\nEND\nTYPE \"after\"") == "after\n");
  CHECK(output_of("n = 3\nWHILE n > 0 DO\nTYPE n\nn = n - 1\nEND") == "3\n2\n1\n");
  CHECK(output_of("n = 0\nWHILE n > 0\nTYPE n\nEND\nTYPE \"done\"") == "done\n");  // DO omitted [ext]
  CHECK(output_of("n = 0\nDO\nn = n + 1\nUNTIL n >= 3\nTYPE n") == "3\n");
  CHECK(output_of("FOR i = 1 TO 10\nIF i == 3 THEN\nEXIT\nEND\nEND\nTYPE i") == "3\n");
  CHECK(output_of("FOR i = 1 TO 4\nIF i == 2 THEN\nNEXT\nEND\nTYPE i, /S\nEND\nTYPE \"\"") == "134\n");
}

TEST_CASE("GOTO and labels", "[evaluator][control]") {
  CHECK(output_of("n = 0\n10 n = n + 1\nIF n < 3 GOTO 10\nTYPE n") == "3\n");
  CHECK(output_of("GOTO 20\nTYPE \"skipped\"\n20\nTYPE \"here\"") == "here\n");  // label alone
  CHECK(output_of("FOR i = 1 TO 10\nIF i == 4 GOTO 99\nEND\n99 TYPE i") == "4\n");  // leaves a block
}

TEST_CASE("CALL by reference and by value", "[evaluator][call]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  a = 1
  b = 1
  CALL inc(a, b + 0)
  TYPE a, b
  CALL inc(c, 5)        ; c gets its value through the reference
  TYPE c
  CALL inc((a), 1)      ; (a) is by value
  TYPE a
  CALL opt(1, , 3)
  arr[2] = 7
  CALL first(arr[])
.END
.PROGRAM inc(x, y)
  x = 10 * y
  y = 99
.END
.PROGRAM opt(a, b, c)
  TYPE DEFINED(a), DEFINED(b), DEFINED(c)
.END
.PROGRAM first(v[])
  TYPE v[2]
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "10 1\n50\n10\n-1 0 -1\n7\n");
}

TEST_CASE("recursion", "[evaluator][call]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  CALL fact(5, r)
  TYPE r
.END
.PROGRAM fact(n, result)
  IF n <= 1 THEN
    result = 1
    RETURN
  END
  CALL fact(n - 1, sub)
  result = n * sub
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "120\n");
}

TEST_CASE("RETURN and STOP", "[evaluator][control]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\nCALL sub()\nTYPE \"back\"\nSTOP\nTYPE \"never\"\n.END\n"
                       ".PROGRAM sub()\nTYPE \"in\"\nRETURN\nTYPE \"never\"\n.END\n");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "in\nback\n");
}

TEST_CASE("runtime errors name the program, step and line", "[evaluator][errors]") {
  InterpreterFixture f;
  const auto r = f.run("; header comment\n.PROGRAM main()\n  a = 1\n\n  TYPE a + zz\n.END\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Undefined value*");
  CHECK(r.error.detail == "zz");
  CHECK(r.error.program == "main");
  CHECK(r.error.line == 5);
  CHECK(r.error.step == 3);
  CHECK(r.error.source_line == "  TYPE a + zz");
  CHECK(r.step == 3);
  CHECK(asimov::interpreter::format_diagnostic(r.error) ==
        "*Undefined value*  zz\n main, step 3 (test.v2:5)\n      TYPE a + zz\n");
}

TEST_CASE("runtime error kinds", "[evaluator][errors]") {
  auto error_of = [](const std::string& body) {
    InterpreterFixture f;
    const auto r = f.run(".PROGRAM main()\n" + body + "\n.END\n");
    INFO(f.load_report);
    REQUIRE(f.loaded);
    REQUIRE(r.status == RunStatus::error);
    return r.error.message;
  };
  CHECK(error_of("x = 1 / 0") == "*Division by zero*");
  CHECK(error_of("x = 5 MOD 0") == "*Division by zero*");
  CHECK(error_of("x = SQRT(-1)") == "*Illegal value*");
  CHECK(error_of("$a = \"a\"\nb = 1\nx = $a + b") == "*Illegal value*");  // not visible: run time
  CHECK(error_of("x = TRANS(1,2,3)") == "*Illegal value*");       // use SET
  CHECK(error_of("y = 3\nSET x = y") == "*Illegal value*");  // SET x = 3 is a load error (the syntax shows it)
  // An array used as a scalar: in one program a load error (test_vplus_builtins.cpp), across
  // programs when the step runs.
  CHECK(error_of("a[1] = 1\nCALL q()\n.END\n.PROGRAM q()\nx = a") == "*Illegal value*");
  CHECK(error_of("x = a[-1]") == "*Illegal value*");
  CHECK(error_of("x = a[2]") == "*Undefined value*");
  CHECK(error_of("CALL nowhere()") == "*Undefined program or variable name*");
  CHECK(error_of("FOR i = 1 TO 2 STEP 0\nEND") == "*Illegal value*");
  CHECK(error_of("SPEED 0") == "*Illegal value*");
  CHECK(error_of("SPEED 101") == "*Illegal value*");
  CHECK(error_of("x = 1e300 * 1e300") == "*Illegal value*");
  CHECK(error_of("x = ASIN(2)") == "*Illegal value*");
}

TEST_CASE("too many arguments", "[evaluator][errors]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\nCALL sub(1, 2)\n.END\n.PROGRAM sub(a)\n.END\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Illegal value*");
}

TEST_CASE("runaway programs stop", "[evaluator][limits]") {
  InterpreterFixture f;
  f.interp.limits().max_statements = 1000;
  auto r = f.run(".PROGRAM main()\n10 GOTO 10\n.END\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Too many statements*");

  InterpreterFixture g;
  r = g.run(".PROGRAM main()\nCALL main()\n.END\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Too many nested calls*");
  CHECK(r.error.step == 1);

  InterpreterFixture h;
  h.interp.limits().max_call_depth = 10;
  r = h.run(".PROGRAM main()\nn = n + 1\nCALL main()\n.END\n.PROGRAM x()\n.END", "main");
  REQUIRE(r.status == RunStatus::error);  // n undefined at first: an error before any call
}

TEST_CASE("call depth limit", "[evaluator][limits]") {
  InterpreterFixture f;
  f.interp.limits().max_call_depth = 10;
  const auto r = f.run(".PROGRAM main()\nn = 0\nCALL deep(n)\n.END\n.PROGRAM deep(n)\nn = n + 1\nCALL deep(n)\n.END\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Too many nested calls*");
  CHECK(r.error.program == "deep");
}

TEST_CASE("globals keep their values between programs and runs", "[evaluator]") {
  InterpreterFixture f;
  auto r = f.run(".PROGRAM main()\ncount = 41\nCALL other()\n.END\n.PROGRAM other()\ncount = count + 1\n.END\n");
  REQUIRE(r.status == RunStatus::completed);
  r = f.run(".PROGRAM show()\nTYPE count\n.END\n", "show");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "42\n");
}

TEST_CASE("AUTO gives each call its own copy, LOCAL is per program", "[evaluator][call]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  CALL fib(10, r)
  TYPE r
  CALL counter()
  CALL counter()
  count = 100
  CALL counter()
  TYPE count
.END
.PROGRAM fib(n, result)
  AUTO REAL r1, r2
  IF n < 2 THEN
    result = n
    RETURN
  END
  CALL fib(n - 1, r1)
  CALL fib(n - 2, r2)
  result = r1 + r2
.END
.PROGRAM counter()
  LOCAL count
  IF NOT DEFINED(count) THEN
    count = 0
  END
  count = count + 1
  TYPE count
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "55\n1\n2\n3\n100\n");
}

TEST_CASE("CASE with VALUE lists and ANY", "[evaluator][control]") {
  const std::string prog =
      "FOR k = 0 TO 4\n"
      "  CASE k OF\n"
      "    VALUE 0:\n"
      "      TYPE \"zero\"\n"
      "    VALUE 1, 2:\n"
      "      TYPE \"small\"\n"
      "    VALUE 3\n"          // the colon is optional
      "      TYPE \"three\"\n"
      "    ANY\n"
      "      TYPE \"other\"\n"
      "  END\n"
      "END\n"
      "CASE 9 OF\n"
      "  VALUE 1:\n"
      "    TYPE \"no\"\n"
      "END\n"
      "TYPE \"after\"";
  CHECK(output_of(prog) == "zero\nsmall\nsmall\nthree\nother\nafter\n");
  // EXIT inside a CASE leaves the enclosing loop: CASE is not a loop.
  CHECK(output_of("FOR i = 1 TO 5\nCASE i OF\nVALUE 3:\nEXIT\nEND\nEND\nTYPE i") == "3\n");
}

TEST_CASE("ELSEIF and ELIF", "[evaluator][control]") {
  const std::string prog =
      "FOR x = 1 TO 4\n"
      "  IF x == 1 THEN\n"
      "    TYPE \"one\"\n"
      "  ELSEIF x == 2 THEN\n"
      "    TYPE \"two\"\n"
      "  ELIF x == 3\n"
      "    TYPE \"three\"\n"
      "  ELSE\n"
      "    TYPE \"many\"\n"
      "  END\n"
      "END";
  CHECK(output_of(prog) == "one\ntwo\nthree\nmany\n");
  CHECK(output_of("IF 0 THEN\nTYPE 1\nELSEIF 0\nTYPE 2\nEND\nTYPE 3") == "3\n");
}

TEST_CASE("location functions", "[evaluator]") {
  CHECK(output_of("SET a = SHIFT(TRANS(1, 2, 3) BY 10, 20, 30)\nTYPE DX(a), DY(a), DZ(a)") == "11 22 33\n");
  CHECK(output_of("SET a = TRANS(,,300)\nTYPE DZ(a), DX(a)") == "300 0\n");
  CHECK(output_of("SET a = TRANS(100, 0, 0, 90, 0, 0):TRANS(10)\nTYPE /F0.3, DX(a), DY(a)") == "100.00010.000\n");
  CHECK(output_of("SET a = INVERSE(TRANS(1, 2, 3))\nTYPE DX(a), DY(a), DZ(a)") == "-1 -2 -3\n");
  CHECK(output_of("SET a = RZ(90):TRANS(1)\nTYPE /F0.3, DX(a), DY(a)") == "0.0001.000\n");
  CHECK(output_of("TYPE DISTANCE(TRANS(3, 4), NULL)") == "5\n");
  CHECK(output_of("SET f = FRAME(TRANS(1), TRANS(2), TRANS(1, 5), TRANS(7, 8, 9))\n"
                  "DECOMPOSE d[0] = f\nTYPE d[0], d[1], d[2], d[3], d[4], d[5]") == "7 8 9 0 0 0\n");
  CHECK(output_of("SET f = FRAME(NULL, TRANS(0, 1), TRANS(-1), NULL)\nTYPE DX(f:TRANS(1)), DY(f:TRANS(1))") == "0 1\n");
  CHECK(output_of("TYPE LAST(a[])\na[3] = 1\na[7] = 1\nTYPE LAST(a[])") == "-1\n7\n");
  CHECK(output_of("DECOMPOSE d[0] = TRANS(1, 2, 3, 10, 20, 30)\nTYPE d[0], d[1], d[2], d[3], d[4], d[5]") ==
        "1 2 3 10 20 30\n");
}

TEST_CASE("signals and SIG", "[evaluator][io]") {
  CHECK(output_of("SIGNAL 1, -2, 2001\nTYPE SIG(1), SIG(-2), SIG(1, 2001), SIG(2), SIG(-1001)") == "-1 -1 -1 0 -1\n");
  CHECK(output_of("SIGNAL 3\nSIGNAL -3, 0\nTYPE SIG(3)") == "0\n");
  InterpreterFixture f;
  auto r = f.run(".PROGRAM main()\nSIGNAL 1001\n.END\n");
  CHECK(r.error.message == "*Illegal value*");  // programs may not set inputs
  r = f.run(".PROGRAM bad()\nx = SIG(600)\n.END\n", "bad");
  CHECK(r.error.message == "*Illegal value*");
  r = f.run(".PROGRAM on()\nSIGNAL 5\n.END\n.PROGRAM show()\nTYPE SIG(5)\n.END\n", "on");
  REQUIRE(r.status == RunStatus::completed);
  REQUIRE(f.interp.run("show").status == RunStatus::completed);  // signals persist
  CHECK(f.out.str() == "-1\n");
}

TEST_CASE("timers follow the simulated clock", "[evaluator][io]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  TIMER 2 = 10
  TYPE TIMER(2)
  MOVE #PPOINT(20, -90, 90, 0, 0, 0)
  BREAK
  TYPE TIMER(2) > 10
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "10\n-1\n");
  InterpreterFixture g;
  CHECK(g.run(".PROGRAM main()\nTIMER 17 = 1\n.END\n").error.message == "*Illegal value*");
}

TEST_CASE("$MID", "[evaluator]") {
  CHECK(output_of("TYPE $MID(\"abcdef\", 2, 3), $MID(\"abc\", 3, 9), \"|\", $MID(\"abc\", 5, 1), \"|\"") == "bcdc||\n");
}

TEST_CASE("V+ constructs that load but are not simulated", "[evaluator][vplus]") {
  InterpreterFixture f;
  auto r = f.run(R"(.PROGRAM main()
  ACCEL 50, 50
  ATTACH ()
  SELECT ROBOT = 1
  ACCEL 100
  TYPE "still running"
  ATTACH (lun, 4) "SERIAL:1"
  TYPE "never"
.END
)");
  INFO(f.load_report);
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Not supported in simulation*");
  CHECK(r.error.detail.rfind("ATTACH \"SERIAL:1\"; network and serial I/O are not simulated", 0) == 0);
  CHECK(r.error.step == 6);
  CHECK(f.out.str() == "still running\n");
  REQUIRE(r.warnings.size() == 1);  // SELECT; ACCEL (docs/blending.md) and the robot's ATTACH () (§7b) are simulated
  CHECK(r.warnings[0].detail == "SELECT");
  CHECK(r.warnings[0].warning);
  CHECK(r.warnings[0].step == 3);
  InterpreterFixture g;
  r = g.run(".PROGRAM main()\n  read = 2\n  TYPE read\n.END\n");  // not followed by "=": a name
  CHECK(r.status == RunStatus::completed);
}

TEST_CASE("no short-circuit: both operands are evaluated (assumption)", "[evaluator][errors]") {
  InterpreterFixture f;
  auto r = f.run(".PROGRAM main()\nx = 0 AND 1 / 0\n.END\n");
  CHECK(r.error.message == "*Division by zero*");
  r = f.run(".PROGRAM b()\nIF 1 OR undefined.q THEN\nEND\n.END\n", "b");
  CHECK(r.error.message == "*Undefined value*");
}

TEST_CASE("RANDOM is uniform in 0 <= x < 1", "[evaluator]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\nok = TRUE\nFOR i = 1 TO 1000\nx = RANDOM\n"
                       "IF x < 0 OR x >= 1 THEN\nok = FALSE\nEND\nEND\nTYPE ok\n.END\n");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "-1\n");
}

TEST_CASE("$ENCODE formats like TYPE", "[evaluator][type]") {
  CHECK(output_of("$s = $ENCODE(\"x=\", 3, \" \", /F6.2, 1/3)\nTYPE $s, \"|\", LEN($s)") == "x=3   0.33|10\n");
  CHECK(output_of("TYPE $ENCODE(1, 2) + \"!\"") == "1 2!\n");
  InterpreterFixture f;
  CHECK_FALSE(f.load(".PROGRAM p()\n$s = $ENCODE(/C2, 1)\n.END\n").empty());
}
