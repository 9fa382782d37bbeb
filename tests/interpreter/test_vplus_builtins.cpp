// V+ built-ins of issue 31: DECOMPOSE a[], SPEED(select), $TIME, $DECODE, CALLS, STATE(3), the
// scalar-or-array check and the bare WAIT loop's limit (dialect §4, §6, §7).
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

#include <regex>

using asimov::interpreter::RunStatus;
using asimov::test::InterpreterFixture;

namespace {

std::string program(const std::string& body) { return ".PROGRAM main()\n" + body + "\n.END\n"; }

std::string outcome(const std::string& body) {
  InterpreterFixture f;
  return asimov::test::outcome_of(f, program(body));
}

// The load errors' details.
std::vector<std::string> load_errors(const std::string& text) {
  InterpreterFixture f;
  std::vector<std::string> out;
  for (const auto& d : f.load(text))
    if (!d.warning) out.push_back(d.detail);
  return out;
}

}  // namespace

TEST_CASE("DECOMPOSE a[] fills a[0] to a[5], a[k] from k", "[builtins]") {
  // The PUMA at READY: the tool's place and orientation (x y z y p r).
  const std::string whole = outcome("DECOMPOSE p[] = HERE\nTYPE LAST(p[]), p[0], p[1], p[2]");
  const std::string from3 = outcome("DECOMPOSE p[3] = HERE\nTYPE LAST(p[]), p[3], p[4], p[5]");
  CHECK(whole.substr(0, 2) == "5 ");
  CHECK(from3.substr(0, 2) == "8 ");
  CHECK(whole.substr(2) == from3.substr(2));
  CHECK(outcome("DECOMPOSE j[] = #PPOINT(1, 2, 3, 4, 5, 6)\nTYPE j[0], j[5], LAST(j[])") == "1 6 5\n");
  CHECK(outcome("DECOMPOSE j[2] = TRANS(1, 2, 3)\nTYPE j[2], j[3], j[4], j[7]") == "1 2 3 0\n");
  // a[] is still refused where no array can stand.
  CHECK(load_errors(program("x = a[]")) == std::vector<std::string>{"a[] is allowed only as a CALL argument"});
}

TEST_CASE("SPEED(select): the monitor speed, the program speed and the next motion's", "[builtins]") {
  CHECK(outcome("TYPE SPEED(1), SPEED(2), SPEED(3)") == "100 100 100\n");
  CHECK(outcome("SPEED 30 ALWAYS\nSPEED 70\nTYPE SPEED(2), SPEED(3)\nMOVE #PPOINT(0, -90, 90, 0, 0, 10)\n"
                "TYPE SPEED(2), SPEED(3)") == "30 70\n30 30\n");
  CHECK(outcome("old = SPEED(2)\nSPEED 10 ALWAYS\nSPEED old ALWAYS\nTYPE SPEED(2)") == "100\n");
  CHECK(outcome("TYPE SPEED(9)") == "ERROR *Not supported in simulation* SPEED(9)");
  InterpreterFixture f;
  f.interp.set_monitor_speed(25);
  CHECK(asimov::test::outcome_of(f, program("TYPE SPEED(1)")) == "25\n");
}

TEST_CASE("$TIME: the clock without arguments, packed date and time with them", "[builtins]") {
  const std::string now = outcome("TYPE $TIME()");
  CHECK(std::regex_match(now, std::regex(R"(\d\d-(JAN|FEB|MAR|APR|MAY|JUN|JUL|AUG|SEP|OCT|NOV|DEC)-\d{4} \d\d:\d\d:\d\d\n)")));
  // 2024-03-15 = (44 * 512) + (3 * 32) + 15; 13:45:30 = 13 * 2048 + 45 * 32 + 15.
  CHECK(outcome("TYPE $TIME(22639, 28079)") == "15-MAR-2024 13:45:30\n");
  CHECK(outcome("TYPE $TIME(22639)") == "15-MAR-2024 00:00:00\n");
  CHECK(outcome("TYPE $TIME(22624)") == "ERROR *Illegal value* $TIME: date 22624 is not a packed date");
  CHECK(outcome("TYPE $TIME(-1)") == "ERROR *Illegal value* $TIME: date -1 is not a packed date");
}

TEST_CASE("$DECODE takes the front of a string variable", "[builtins]") {
  CHECK(outcome("$s = \"10, 20 ,30\"\n"
                "WHILE LEN($s) > 0 DO\n"
                "  $w = $DECODE($s, \", \", 0)\n"
                "  $sep = $DECODE($s, \", \", 1)\n"
                "  TYPE \"[\", $w, \"|\", $sep, \"]\"\n"
                "END") == "[10|, ]\n[20| ,]\n[30|]\n");
  CHECK(outcome("$s = \"abc\"\n$w = $DECODE($s, \";\", 0)\nTYPE $w, \"|\", $s, \"|\", LEN($s)") == "abc||0\n");
  CHECK(load_errors(program("$w = $DECODE(\"abc\", \",\", 0)")) == std::vector<std::string>{"$DECODE needs a string variable"});
}

TEST_CASE("CALLS calls the program the string names", "[builtins]") {
  const std::string text = ".PROGRAM main()\n  $p = \"twice\"\n  n = 4\n  CALLS $p(n)\n  TYPE n\n"
                           "  CALLS \"HELLO\"\n  $p = \"absent\"\n  CALLS $p()\n.END\n"
                           ".PROGRAM twice(x)\n  x = 2 * x\n.END\n.PROGRAM hello()\n  TYPE \"hello\"\n.END\n";
  InterpreterFixture f;
  const auto r = f.run(text);
  REQUIRE(f.loaded);
  CHECK(f.out.str() == "8\nhello\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Undefined program or variable name*");
  CHECK(r.error.detail == "absent");
  CHECK(r.step == 7);
  CHECK(outcome("x = 1\nCALLS x").rfind("ERROR *Illegal value*", 0) == 0);  // a real names no program
  CHECK(load_errors(program("CALLS 3")) == std::vector<std::string>{"expected string"});
}

TEST_CASE("check: a name is a scalar or an array in one program", "[builtins]") {
  CHECK(load_errors(program("AUTO a\nAUTO a[5]")) == std::vector<std::string>{"a is used both as a scalar and as an array"});
  CHECK(load_errors(program("x = 1\nx[2] = 3")) == std::vector<std::string>{"x is used both as a scalar and as an array"});
  CHECK(load_errors(".PROGRAM main(a[])\n  TYPE a\n.END\n")
        == std::vector<std::string>{"a is used both as a scalar and as an array"});
  // Each program is its own scope; DEFINED, DECOMPOSE and by-reference arguments decide nothing.
  CHECK(load_errors(".PROGRAM a()\n  AUTO v\n  v = 1\n.END\n.PROGRAM b()\n  AUTO v[3]\n  v[1] = 2\n.END\n").empty());
  CHECK(load_errors(program("DECOMPOSE d = HERE\nTYPE d[1], DEFINED(d)\nCALL q(d)")).empty());
  CHECK(load_errors(program("$a = \"x\"\na[1] = 2\n#a = #PPOINT(0,0,0,0,0,0)")).empty());  // three names
}

TEST_CASE("a bare WAIT loop on a signal nothing drives stops at the wait limit with the hint", "[builtins]") {
  InterpreterFixture f;
  f.interp.limits().max_wait_s = 2;
  const auto r = f.run(program("10 IF NOT SIG(1001) THEN\n  WAIT\n  GOTO 10\nEND\nTYPE \"never\""));
  REQUIRE(f.loaded);
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Wait limit exceeded*");
  CHECK(r.error.detail == "a loop of WAIT still waiting after 2 s; no device in the cell drives signal 1001");
  // WAITs with time passing between them (motions) are separate waits.
  InterpreterFixture g;
  g.interp.limits().max_wait_s = 0.05;
  CHECK(asimov::test::outcome_of(g, program("FOR i = 1 TO 3\n  WAIT\n  WAIT\n  DRIVE 1, 1, 100\nEND\nTYPE \"done\""))
        == "done\n");
}
