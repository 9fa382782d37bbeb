// The public API: atomic LOAD, diagnostics with program and step, names, replacing programs.
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

using asimov::test::InterpreterFixture;
using asimov::val::RunStatus;

TEST_CASE("a load with any error loads nothing and reports everything", "[interpreter]") {
  InterpreterFixture f;
  const auto d = f.load(".PROGRAM good()\n  TYPE 1\n.END\n"
                        ".PROGRAM pick()\n  x = 1\n  total = (n + 2 * k\n  IF x THEN\n  GOTO 77\n.END\n");
  REQUIRE(d.size() == 3);
  CHECK(d[0].line == 6);
  CHECK(d[0].program == "pick");
  CHECK(d[0].step == 2);
  CHECK(d[1].detail == "IF without END");
  CHECK(d[1].line == 7);
  CHECK(d[1].column == 3);
  CHECK(d[2].detail == "undefined label 77");
  CHECK(asimov::val::format_diagnostic(d[0]) ==
        "*Syntax error*  expected \")\"\n test.v2:6:21  (pick, step 2)\n      total = (n + 2 * k\n                        ^\n");
  CHECK_FALSE(f.interp.has_program("good"));
  CHECK(f.interp.program_names().empty());
}

TEST_CASE("program names: load order, any case, replacement", "[interpreter]") {
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM Second()\nTYPE \"one\"\n.END\n.PROGRAM first()\n.END\n").empty());
  CHECK(f.interp.program_names() == std::vector<std::string>{"second", "first"});
  CHECK(f.interp.has_program("SECOND"));
  CHECK_FALSE(f.interp.has_program("third"));
  REQUIRE(f.interp.run("SeCoNd").status == RunStatus::completed);
  REQUIRE(f.load(".PROGRAM second()\nTYPE \"two\"\n.END\n").empty());  // replaced
  REQUIRE(f.interp.run("second").status == RunStatus::completed);
  CHECK(f.out.str() == "one\ntwo\n");
  CHECK(f.interp.program_names().size() == 2);
}

TEST_CASE("a CALL to a program loaded later resolves at run time", "[interpreter]") {
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM main()\nCALL later()\n.END\n").empty());
  auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Undefined program or variable name*");
  CHECK(r.error.detail == "later");
  REQUIRE(f.load(".PROGRAM later()\nTYPE \"later\"\n.END\n").empty());
  r = f.interp.run("main");
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "later\n");
}

TEST_CASE("running an unknown program, a missing file", "[interpreter]") {
  InterpreterFixture f;
  const auto r = f.interp.run("nothing");
  CHECK(r.status == RunStatus::error);
  CHECK(r.error.message == "*Undefined program or variable name*");
  const auto d = f.interp.load_file("/nonexistent/file.v2");
  REQUIRE(d.size() == 1);
  CHECK(d[0].message == "*File not found*");
}

TEST_CASE("a completed run reports the program and no step", "[interpreter]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\nx = 1\n.END\n");
  CHECK(r.status == RunStatus::completed);
  CHECK(r.program == "main");
  CHECK(r.line == 0);
  CHECK(r.step == 0);
}

TEST_CASE("at most 20 load errors", "[interpreter]") {
  InterpreterFixture f;
  std::string text = ".PROGRAM p()\n";
  for (int i = 0; i < 30; ++i) text += "  x = (\n";
  text += ".END\n";
  CHECK(f.load(text).size() == 20);
}
