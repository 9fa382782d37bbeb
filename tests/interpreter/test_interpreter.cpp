// The public API: LOAD as V+ does it (programs with errors marked not executable), diagnostics with program and step, names, replacing programs.
#include "interpreter_fixture.hpp"
#include "interpreter/src/errors.hpp"
#include "../support/scratch.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>

#include <sys/stat.h>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;

TEST_CASE("a load reports every error and marks the program with errors not executable", "[interpreter]") {
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
  CHECK(asimov::interpreter::format_diagnostic(d[0]) ==
        "*Syntax error*  expected \")\"\n test.v2:6:21  (pick, step 2)\n      total = (n + 2 * k\n                        ^\n");
  // As V+ loads: pick is marked not executable, good loads and runs.
  CHECK(f.interp.program_names() == std::vector<std::string>{"good", "pick"});
  CHECK(f.interp.run("good").status == RunStatus::completed);
  CHECK(f.out.str() == "1\n");
  const auto r = f.interp.run("pick");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Program not executable*");
  CHECK(r.error.detail == "pick");
  CHECK(f.interp.not_executable_from("good") == std::nullopt);
  CHECK(f.interp.not_executable_from("pick") == "pick");
}

TEST_CASE("calling a program marked not executable stops with V+'s error", "[interpreter]") {
  InterpreterFixture f;
  const auto d = f.load(".PROGRAM main()\n  TYPE \"main\"\n  CALL ok()\n  CALL bad(1)\n  TYPE \"never\"\n.END\n"
                        ".PROGRAM ok()\n  TYPE \"ok\"\n.END\n"
                        ".PROGRAM bad(n)\n  TYPE n +\n.END\n"
                        ".PROGRAM starter()\n  EXECUTE 1 bad(2)\n.END\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].program == "bad");
  CHECK(d[0].line == 11);
  CHECK(f.interp.not_executable_from("main") == "bad");
  CHECK(f.interp.not_executable_from("ok") == std::nullopt);
  auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Program not executable*");
  CHECK(r.error.detail == "bad");
  CHECK(r.program == "main");
  CHECK(r.step == 3);
  CHECK(f.out.str() == "main\nok\n");
  r = f.interp.run("starter");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Program not executable*");
  CHECK(asimov::interpreter::error_code(r.error.message) == -304);
  // Loading a corrected bad makes main run through.
  REQUIRE(f.load(".PROGRAM bad(n)\n  TYPE n + 1\n.END\n").empty());
  f.out.str("");
  CHECK(f.interp.run("main").status == RunStatus::completed);
  CHECK(f.out.str() == "main\nok\n2\nnever\n");
}

TEST_CASE("an error outside every program still loads nothing", "[interpreter]") {
  InterpreterFixture f;
  const auto d = f.load(".PROGRAM good()\n  TYPE 1\n.END\nstray text\n.PROGRAM other()\n.END\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].detail == "expected a statement");  // the stray line, outside every program
  CHECK(f.interp.program_names().empty());
  // A program without .END is not loaded; the rest is.
  InterpreterFixture g;
  const auto e = g.load(".PROGRAM good()\n  TYPE 1\n.END\n.PROGRAM open()\n  TYPE 2\n");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == ".PROGRAM without .END");
  CHECK(g.interp.program_names() == std::vector<std::string>{"good"});
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
  const auto diags = f.load(".PROGRAM main()\nCALL later()\n.END\n");
  REQUIRE(diags.size() == 1);  // a warning at load time, an error when the CALL runs
  CHECK(diags[0].warning);
  CHECK(diags[0].message == "*Undefined program or variable name*");
  CHECK(diags[0].detail == "later");
  CHECK(diags[0].step == 1);
  CHECK(f.interp.has_program("main"));
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
  // Not a regular file: named as what it is, and nothing is opened (a FIFO with no writer would
  // block the read for ever: this test would hang).
  const auto folder = f.interp.load_file("/");
  REQUIRE(folder.size() == 1);
  CHECK(folder[0].message == "*Cannot read file*");
  CHECK(folder[0].detail == "/: is a folder, not a file");
  const std::string fifo = (asimov::test::scratch_dir("load-fifo") / "p.v2").string();
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  const auto pipe = f.interp.load_file(fifo);
  REQUIRE(pipe.size() == 1);
  CHECK(pipe[0].message == "*Cannot read file*");
  CHECK(pipe[0].detail == fifo + ": is a FIFO, not a regular file");
  const auto dev = f.interp.load_file("/dev/null");
  REQUIRE(dev.size() == 1);
  CHECK(dev[0].detail == "/dev/null: is a device, not a regular file");
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
  const auto d = f.load(text);
  REQUIRE(d.size() == 21);  // 20 errors and the note that says so
  CHECK(d[19].message == "*Syntax error*");
  CHECK(d[20].message == "*Too many errors*");
  CHECK(d[20].detail == "10 more not reported (at most 20 per LOAD)");
  CHECK(asimov::interpreter::format_diagnostic(d[20]) == "*Too many errors*  10 more not reported (at most 20 per LOAD)\n test.v2\n");
}

TEST_CASE("data sections assign globals when the load succeeds", "[interpreter][data]") {
  InterpreterFixture f;
  const auto r = f.run(R"(; data first, programs after, any order
.LOCATIONS
pick      300 200 50 0 180 0          ; transformation
#safe     0, -90, 180, 0, 0, 0        ; precision point, commas allowed
pal[2]    450 -120 12.5 90 90 0
.END
.REALS
count  3
m[1,2] -2.5e1
.END
.STRINGS
$greeting "Hello; world"
.END
.PROGRAM main()
  TYPE count, m[1,2], " ", $greeting
  DECOMPOSE d[0] = pick
  TYPE d[0], d[1], d[2], d[4]
  DECOMPOSE j[0] = #safe
  TYPE j[2]
  TYPE DX(pal[2]), DZ(pal[2])
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "3 -25 Hello; world\n300 200 50 180\n180\n450 12.5\n");
}

TEST_CASE("data section errors", "[interpreter][data]") {
  auto errors = [](const std::string& text) {
    InterpreterFixture f;
    return f.load(text);
  };
  auto d = errors(".LOCATIONS\n#p 1 2 3\n.END\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].line == 2);
  CHECK(d[0].detail == "a precision point takes 6 joint values");
  CHECK(errors(".LOCATIONS\np 1 2 3 4 5\n.END\n").size() == 1);
  CHECK(errors(".REALS\nx 1 2\n.END\n").size() == 1);
  CHECK(errors(".REALS\n$x \"a\"\n.END\n").size() == 1);
  CHECK(errors(".STRINGS\n$x 3\n.END\n").size() == 1);
  d = errors("\n.REALS\nx 1\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].detail == "data section without .END");
  CHECK(d[0].line == 2);
  CHECK(errors(".PROGRAM p()\n.REALS\n.END\n").size() >= 1);
  CHECK(errors(".REALS\nx = 1\n.END\n").size() == 1);  // syntax error in a data line
  // Nothing is assigned when a data row is wrong; an error in a program marks only the program.
  InterpreterFixture f;
  REQUIRE(f.load(".REALS\nkeep 1\n.END\n").empty());
  REQUIRE(f.load(".REALS\nkeep 2\nbad 1 2\n.END\n.PROGRAM p()\n.END\n").size() == 1);
  CHECK_FALSE(f.interp.has_program("p"));
  auto r = f.run(".PROGRAM show()\nTYPE keep\n.END\n", "show");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "1\n");
  REQUIRE(f.load(".REALS\nkeep 3\n.END\n.PROGRAM p()\nGOTO 5\n.END\n").size() == 1);
  CHECK(f.interp.not_executable_from("p") == "p");
  r = f.interp.run("show");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "1\n3\n");
}

TEST_CASE("a block opener with a syntax error causes no second error", "[interpreter]") {
  InterpreterFixture f;
  auto d = f.load(".PROGRAM p()\n  IF a = b THEN\n    x = 1\n  ELSE\n    x = 2\n  END\n.END\n");
  REQUIRE(d.size() == 1);
  CHECK(d[0].line == 2);
  d = f.load(".PROGRAM p()\n  WHILE x > 0 DO\n    x = x - 1\n  END x\n.END\n");
  REQUIRE(d.size() == 1);  // the END with a syntax error: WHILE is not reported unclosed
  CHECK(d[0].line == 4);
  d = f.load(".PROGRAM p()\n  x = (1\n.END\n.PROGRAM q()\n  END\n.END\n");
  CHECK(d.size() == 2);  // another program's block errors still count
}

TEST_CASE("PROCEED and RETRY continue a stopped execution", "[interpreter][resume]") {
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM main()\n  TYPE \"a\"\n  x = 1 / d\n  TYPE \"b\", x\n.END\n"
                 ".PROGRAM fix()\n  d = 4\n.END\n").empty());
  CHECK_FALSE(f.interp.can_resume());
  auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::error);  // d undefined
  CHECK(f.interp.can_resume());
  REQUIRE(f.interp.run("fix").status == RunStatus::completed);  // a run in between keeps it
  CHECK(f.interp.can_resume());
  r = f.interp.retry();  // re-runs x = 1 / d
  CHECK(r.status == RunStatus::completed);
  CHECK(r.program == "main");
  CHECK(f.out.str() == "a\nb0.25\n");
  CHECK_FALSE(f.interp.can_resume());

  r = f.interp.run("main");  // d is 4 now: completes
  REQUIRE(r.status == RunStatus::completed);
  REQUIRE(f.load(".PROGRAM skip()\n  TYPE \"1\"\n  y = nothing\n  TYPE \"2\"\n.END\n").empty());
  REQUIRE(f.interp.run("skip").status == RunStatus::error);
  f.out.str("");
  r = f.interp.proceed();  // skips y = nothing
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "2\n");

  r = f.interp.proceed();
  CHECK(r.status == RunStatus::error);
  CHECK(r.error.message == "*No program to resume*");

  REQUIRE(f.interp.run("skip").status == RunStatus::error);
  f.interp.abort();
  CHECK_FALSE(f.interp.can_resume());
}

TEST_CASE("a stopped execution keeps its call stack and speed", "[interpreter][resume]") {
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM main()\n  SPEED 30 ALWAYS\n  CALL sub(3)\n  TYPE \"back\"\n.END\n"
                 ".PROGRAM sub(n)\n  TYPE n\n  z = zz\n  TYPE n + 1\n.END\n").empty());
  REQUIRE(f.interp.run("main").status == RunStatus::error);
  const auto r = f.interp.proceed();
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "3\n4\nback\n");
}

TEST_CASE("an interrupt stops the run between steps, PROCEED runs the next step", "[interpreter][resume]") {
  InterpreterFixture f;
  std::atomic<bool> interrupt{false};
  f.interp.limits().interrupt = &interrupt;
  REQUIRE(f.load(".PROGRAM main()\n  TYPE 1\n  TYPE 2\n.END\n").empty());
  interrupt = true;
  auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::interrupted);
  CHECK(r.error.message == "*Program interrupted*");
  CHECK(r.error.step == 1);
  CHECK(f.out.str().empty());
  interrupt = false;
  r = f.interp.proceed();
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "1\n2\n");
}
