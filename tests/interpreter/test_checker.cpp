// Stage 2: load-time checks (programs, blocks, labels, functions) and the precedence table.
#include "interpreter/src/checker.hpp"

#include <catch2/catch.hpp>

using namespace asimov::interpreter;

namespace {

std::vector<Diagnostic> check(const std::string& text) {
  Symbols symbols;
  const ParsedSource parsed = parse_source(text, "t.v2");
  REQUIRE(parsed.errors.empty());
  return check_source(parsed, symbols).errors;
}

}  // namespace

TEST_CASE("a clean file compiles every program", "[checker]") {
  Symbols symbols;
  const auto parsed = parse_source("; c\n.PROGRAM a()\nx = 1\n.END\n\n.PROGRAM b(y)\nCALL a()\n.END\n", "t.v2");
  const CheckResult r = check_source(parsed, symbols);
  CHECK(r.errors.empty());
  REQUIRE(r.programs.size() == 2);
  CHECK(r.programs[0].name == "a");
  CHECK(r.programs[1].line == 6);
  CHECK(r.programs[1].params.size() == 1);
}

TEST_CASE("undefined and duplicate labels", "[checker]") {
  auto e = check(".PROGRAM p()\nx = 1\n  GOTO 10\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].message == "*Syntax error*");
  CHECK(e[0].detail == "undefined label 10");
  CHECK(e[0].line == 3);
  CHECK(e[0].column == 3);
  CHECK(e[0].program == "p");
  CHECK(e[0].step == 2);

  e = check(".PROGRAM p()\n10 x = 1\n10 x = 2\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "duplicate label 10");
  CHECK(e[0].line == 3);

  CHECK(check(".PROGRAM p()\n10 x = 1\n.END\n.PROGRAM q()\n10 x = 2\nGOTO 10\n.END\n").empty());  // local
}

TEST_CASE("unclosed blocks are reported at their opening line", "[checker]") {
  auto e = check(".PROGRAM p()\nx = 1\nIF x THEN\nFOR i = 1 TO 3\nEND\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "IF without END");
  CHECK(e[0].line == 3);

  e = check(".PROGRAM p()\nWHILE 1 DO\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "WHILE without END");
  CHECK(e[0].line == 2);

  e = check(".PROGRAM p()\nEND\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "END without a block");

  e = check(".PROGRAM p()\nELSE\n.END\n");
  REQUIRE(e.size() == 1);

  e = check(".PROGRAM p()\nDO\nEND\n.END\n");
  CHECK(e.size() == 2);  // END closes no DO, and DO is never closed
}

TEST_CASE(".PROGRAM without .END and text outside programs", "[checker]") {
  auto e = check("\n.PROGRAM p()\nx = 1\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == ".PROGRAM without .END");
  CHECK(e[0].line == 2);

  e = check(".PROGRAM p()\n.PROGRAM q()\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].line == 1);

  e = check("x = 1\n.PROGRAM p()\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].line == 1);

  CHECK(check(".PROGRAM p()\n.END\n.PROGRAM p()\n.END\n").size() == 1);  // defined twice
}

TEST_CASE("GOTO into a block, EXIT outside a loop", "[checker]") {
  auto e = check(".PROGRAM p()\nGOTO 10\nIF 1 THEN\n10 x = 1\nEND\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "GOTO 10 jumps into a block");
  CHECK(e[0].line == 2);

  CHECK(check(".PROGRAM p()\nIF 1 THEN\nGOTO 10\nEND\n10 x = 1\n.END\n").empty());  // out of a block
  CHECK(check(".PROGRAM p()\nIF 1 THEN\n10 x = 1\nGOTO 10\nEND\n.END\n").empty());  // same block

  e = check(".PROGRAM p()\nEXIT\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "EXIT outside a loop");
}

TEST_CASE("functions are known and have the right arity", "[checker]") {
  CHECK(check(".PROGRAM p()\nx = SIN(1) + ATAN2(1, 2) + MAX(1, 2, 3)\n.END\n").empty());
  auto e = check(".PROGRAM p()\nx = FOO(1)\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "unknown function FOO");  // as written
  e = check(".PROGRAM p()\nx = SIN(1, 2)\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "wrong number of arguments to sin");
}

TEST_CASE("statement arguments", "[checker]") {
  CHECK(check(".PROGRAM p()\nMOVE\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nAPPRO a\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nBREAK 3\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nMOVE a ALWAYS\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nHERE 3\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nx = a[]\n.END\n").size() == 1);
}

TEST_CASE("the precedence table of dialect 3", "[checker]") {
  using ast::Op;
  CHECK(precedence(Op::mul) > precedence(Op::add));
  CHECK(precedence(Op::mod) == precedence(Op::div));
  CHECK(precedence(Op::add) > precedence(Op::eq));
  CHECK(precedence(Op::le) == precedence(Op::ne));
  CHECK(precedence(Op::eq) > precedence(Op::and_));
  CHECK(precedence(Op::band) == precedence(Op::and_));
  CHECK(precedence(Op::and_) > precedence(Op::or_));
  CHECK(precedence(Op::xor_) == precedence(Op::bor));
  CHECK(precedence(Op::compound) > precedence(Op::mul));
}

TEST_CASE("names resolve to slots: parameters first, then globals", "[checker]") {
  Symbols symbols;
  const auto parsed = parse_source(".PROGRAM p(a)\na = b\nCALL q(a)\n.END\n", "t.v2");
  const CheckResult r = check_source(parsed, symbols);
  REQUIRE(r.errors.empty());
  const Instr& assign = r.programs[0].code[0];
  CHECK(assign.target.ref.scope == Scope::param);
  CHECK(assign.target.ref.slot == 0);
  CHECK(assign.args[0].ref.scope == Scope::global);
  CHECK(symbols.globals[static_cast<std::size_t>(assign.args[0].ref.slot)] == "b");
  CHECK(symbols.programs.at(static_cast<std::size_t>(r.programs[0].code[1].program)) == "q");
}

TEST_CASE("declarations precede the first executable statement", "[checker]") {
  CHECK(check(".PROGRAM p(a)\nAUTO b, $s, #q\nLOCAL c\nGLOBAL g\nb = 1\n.END\n").empty());
  auto e = check(".PROGRAM p()\nx = 1\nAUTO b\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].line == 3);
  CHECK(check(".PROGRAM p(a)\nAUTO a\n.END\n").size() == 1);       // a parameter
  CHECK(check(".PROGRAM p()\nAUTO b\nLOCAL b\n.END\n").size() == 1);  // two classes
  CHECK(check(".PROGRAM p()\nAUTO b\nAUTO b\n.END\n").empty());       // repeated [ext]
}

TEST_CASE("a visible mix of strings and numbers is a syntax error", "[checker]") {
  CHECK(check(".PROGRAM p()\nx = \"a\" + 1\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\n$s = 3\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nx = $s\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nx = -$s\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nx = $s * 2\n.END\n").size() == 1);
  CHECK(check(".PROGRAM p()\nx = LEN($s) + 1\n$t = $s + \"x\"\nx = $s == \"a\"\n.END\n").empty());
  CHECK(check(".PROGRAM p()\nx = y + 1\n$t = $CHR(65) + $s\n.END\n").empty());
}

TEST_CASE("an unknown function is named as written, the caret under it", "[checker]") {
  auto e = check(".PROGRAM p()\n  x = 1 + FooBar (2)\n.END\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "unknown function FooBar");
  CHECK(e[0].column == 11);
  e = check(".PROGRAM p()\n  x = foo.x + FOO(2)\n.END\n");  // not the variable foo.x
  REQUIRE(e.size() == 1);
  CHECK(e[0].column == 15);
}
