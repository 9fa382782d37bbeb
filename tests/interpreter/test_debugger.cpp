// The step hook and the program debugger (step_hook.hpp, debugger.hpp): one step at a time
// into and over CALLs, breakpoints, a paused run resumed exactly where it stopped.
#include "interpreter_fixture.hpp"

#include "asimov/interpreter/debugger.hpp"

namespace asimov::test {
namespace {

using interpreter::DebugMode;
using interpreter::DebugStop;
using interpreter::Debugger;
using interpreter::RunStatus;
using interpreter::StepAction;
using interpreter::StepEvent;

const char* const kProgram = R"(.PROGRAM main()
    x = 1
    ; a comment is no step
    CALL inner(x)
    MOVE #PPOINT(10, -80, 80, 0, 0, 0)
    TYPE "x = ", x
.END
.PROGRAM inner(v)
    v = v + 1
    v = v * 10
.END
)";

struct Stepped {
  std::string program;
  int step;
  int depth;
};

// Drives `mode` from DEBUG until the run ends; the places it stopped at.
std::vector<Stepped> stops(InterpreterFixture& f, Debugger& d, DebugMode mode) {
  std::vector<Stepped> out;
  auto r = d.drive(DebugMode::into, false, [&] { return f.interp.run("main"); });
  while (r.status == RunStatus::paused) {
    REQUIRE(d.last_stop() != DebugStop::none);
    out.push_back({d.place().program, d.place().step, d.place().depth});
    r = d.drive(mode, true, [&] { return f.interp.proceed(); });
  }
  INFO(interpreter::format_diagnostic(r.error));
  CHECK(r.status == RunStatus::completed);
  CHECK(d.last_stop() == DebugStop::none);
  return out;
}

std::string text(const std::vector<Stepped>& v) {
  std::string s;
  for (const auto& p : v) s += p.program + ":" + std::to_string(p.step) + "@" + std::to_string(p.depth) + " ";
  return s;
}

}  // namespace

TEST_CASE("the step hook is called before each instruction with its program, step, depth and task", "[debugger]") {
  InterpreterFixture f;
  REQUIRE(f.load(kProgram).empty());
  std::vector<std::string> seen;
  f.interp.set_step_hook([&](const StepEvent& e) {
    seen.push_back(e.program + ":" + std::to_string(e.step) + ":" + std::to_string(e.line) + ":" +
                   std::to_string(e.depth) + ":" + std::to_string(e.task));
    return StepAction::go;
  });
  const auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(seen == std::vector<std::string>{"main:1:2:1:0", "main:3:4:1:0", "inner:1:9:2:0", "inner:2:10:2:0",
                                         "main:4:5:1:0", "main:5:6:1:0"});
  CHECK(f.out.str() == "x = 20\n");
  // Unset again: the next run calls nothing.
  f.interp.set_step_hook({});
  seen.clear();
  REQUIRE(f.interp.run("main").status == RunStatus::completed);
  CHECK(seen.empty());
}

TEST_CASE("a pause asked by the hook is resumed at that instruction, the arm where its motions put it", "[debugger]") {
  InterpreterFixture f;
  REQUIRE(f.load(kProgram).empty());
  f.interp.set_step_hook([&](const StepEvent& e) { return e.program == "main" && e.step == 5 ? StepAction::pause : StepAction::go; });
  const auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::paused);
  CHECK(r.program == "main");
  CHECK(r.step == 5);
  CHECK(f.out.str().empty());  // TYPE has not run
  // The MOVE before it is carried out: the arm is at its target.
  CHECK(f.sim.joints()[0] == Approx(10).margin(1e-6));
  CHECK(f.sim.joints()[1] == Approx(-80).margin(1e-6));
  const double t = f.sim.time_s();
  CHECK(t > 0);
  f.interp.set_step_hook({});
  const auto r2 = f.interp.proceed();
  CHECK(r2.status == RunStatus::completed);
  CHECK(f.out.str() == "x = 20\n");
  CHECK(f.sim.time_s() == t);  // nothing moved again
}

TEST_CASE("XSTEP stops at every step, into CALLs, SSTEP runs a CALL as one step", "[debugger]") {
  {
    InterpreterFixture f;
    REQUIRE(f.load(kProgram).empty());
    Debugger d(f.interp);
    CHECK(text(stops(f, d, DebugMode::into)) == "main:1@1 main:3@1 inner:1@2 inner:2@2 main:4@1 main:5@1 ");
    CHECK(f.out.str() == "x = 20\n");
  }
  {
    InterpreterFixture f;
    REQUIRE(f.load(kProgram).empty());
    Debugger d(f.interp);
    CHECK(text(stops(f, d, DebugMode::over)) == "main:1@1 main:3@1 main:4@1 main:5@1 ");
    CHECK(f.out.str() == "x = 20\n");
  }
}

TEST_CASE("SSTEP at the last step of a CALLed program stops in the caller", "[debugger]") {
  InterpreterFixture f;
  REQUIRE(f.load(kProgram).empty());
  Debugger d(f.interp);
  d.set_breakpoint({"inner", 2});
  auto r = d.drive(DebugMode::run, false, [&] { return f.interp.run("main"); });
  REQUIRE(r.status == RunStatus::paused);
  CHECK(d.last_stop() == DebugStop::breakpoint);
  CHECK(d.place().program == "inner");
  CHECK(d.place().step == 2);
  CHECK(d.place().text == "v = v * 10");
  r = d.drive(DebugMode::over, true, [&] { return f.interp.proceed(); });
  REQUIRE(r.status == RunStatus::paused);
  CHECK(d.last_stop() == DebugStop::step);
  CHECK(d.place().program == "main");
  CHECK(d.place().step == 4);
}

TEST_CASE("breakpoints stop a run each time their step comes, a loop's included", "[debugger]") {
  InterpreterFixture f;
  REQUIRE(f.load(R"(.PROGRAM main()
    FOR i = 1 TO 3
        TYPE i
    END
    TYPE "end"
.END
)").empty());
  Debugger d(f.interp);
  d.set_breakpoint({"main", 2});
  CHECK_FALSE(d.set_breakpoint({"main", 2}));
  std::vector<std::string> at;
  auto r = d.drive(DebugMode::run, false, [&] { return f.interp.run("main"); });
  while (r.status == RunStatus::paused) {
    at.push_back(f.out.str());
    r = d.drive(DebugMode::run, true, [&] { return f.interp.proceed(); });
  }
  CHECK(r.status == RunStatus::completed);
  CHECK(at == std::vector<std::string>{"", "1\n", "1\n2\n"});
  CHECK(f.out.str() == "1\n2\n3\nend\n");
  // Cleared: the run goes through.
  CHECK(d.clear_breakpoint({"main", 2}));
  f.out.str("");
  CHECK(d.drive(DebugMode::run, false, [&] { return f.interp.run("main"); }).status == RunStatus::completed);
  CHECK(f.out.str() == "1\n2\n3\nend\n");
}

TEST_CASE("PAUSE in the program is not the debugger's stop", "[debugger]") {
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM main()\n    PAUSE\n    TYPE \"after\"\n.END\n").empty());
  Debugger d(f.interp);
  d.set_breakpoint({"main", 2});
  auto r = d.drive(DebugMode::run, false, [&] { return f.interp.run("main"); });
  CHECK(r.status == RunStatus::paused);
  CHECK(d.last_stop() == DebugStop::none);
  r = d.drive(DebugMode::run, true, [&] { return f.interp.proceed(); });
  CHECK(r.status == RunStatus::paused);
  CHECK(d.last_stop() == DebugStop::breakpoint);
  r = d.drive(DebugMode::run, true, [&] { return f.interp.proceed(); });
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "after\n");
}

TEST_CASE("a stepped run keeps the arm and the clock between its steps", "[debugger]") {
  InterpreterFixture f;
  REQUIRE(f.load(kProgram).empty());
  Debugger d(f.interp);
  // Stepping keeps the arm state: the step after a MOVE sees the clock at its end.
  auto r = d.drive(DebugMode::into, false, [&] { return f.interp.run("main"); });
  double clock = 0;
  while (r.status == RunStatus::paused) {
    if (d.place().step == 5) clock = f.sim.time_s();
    r = d.drive(DebugMode::over, true, [&] { return f.interp.proceed(); });
  }
  CHECK(clock > 0);
  CHECK(f.sim.time_s() == clock);
}

TEST_CASE("monitor: DEBUG, SSTEP, XSTEP, BPT, NOBPT, PROCEED and ABORT", "[debugger][monitor]") {
  MonitorFixture f;
  REQUIRE(f.load(kProgram).empty());
  CHECK(f.run("SSTEP") == "*No program to resume*  DEBUG or EXECUTE a program first\n    SSTEP\n");
  CHECK(f.run("DEBUG main") == "main, step 1:  x = 1\n");
  CHECK(f.run("XSTEP") == "main, step 3:  CALL inner(x)\n");
  CHECK(f.run("XSTEP") == "inner, step 1:  v = v + 1\n");
  CHECK(f.run("SSTEP") == "inner, step 2:  v = v * 10\n");
  CHECK(f.run("LISTR x") == "x               2\n");
  CHECK(f.run("SSTEP") == "main, step 4:  MOVE #PPOINT(10, -80, 80, 0, 0, 0)\n");
  CHECK(f.run("DO x = 7") == "");
  CHECK(f.run("SSTEP") == "main, step 5:  TYPE \"x = \", x\n");
  CHECK(f.run("STATUS").find("State: paused at step 5\n") != std::string::npos);
  CHECK(f.run("SSTEP") == "x = 7\nProgram completed: main\n");
  CHECK(f.run("XSTEP") == "*No program to resume*  DEBUG or EXECUTE a program first\n    XSTEP\n");
  // Breakpoints: EXECUTE and PROCEED stop there.
  CHECK(f.run("BPT inner, 2") == "");
  CHECK(f.run("BPT main, 5") == "");
  CHECK(f.run("BPT") == "inner, step 2:  v = v * 10\nmain, step 5:  TYPE \"x = \", x\n");
  CHECK(f.run("BPT main, 2") == "*Illegal value*  no instruction at step 2 of main\n    BPT main, 2\n");
  CHECK(f.run("BPT nothere, 1") == "*Undefined program or variable name*  nothere\n    BPT nothere, 1\n");
  CHECK(f.run("EXECUTE main") == "Breakpoint at inner, step 2\ninner, step 2:  v = v * 10\n");
  CHECK(f.run("STATUS").find("State: paused at step 2 of inner\n") != std::string::npos);
  CHECK(f.run("PROCEED") == "Breakpoint at main, step 5\nmain, step 5:  TYPE \"x = \", x\n");
  CHECK(f.run("NOBPT main, 5") == "");
  CHECK(f.run("NOBPT main, 5") == "*Illegal value*  no breakpoint at step 5 of main\n    NOBPT main, 5\n");
  CHECK(f.run("PROCEED") == "x = 20\nProgram completed: main\n");
  CHECK(f.run("NOBPT") == "");
  CHECK(f.run("BPT").empty());
  // ABORT ends a debugged program.
  CHECK(f.run("DEBUG") == "main, step 1:  x = 1\n");
  CHECK(f.run("ABORT") == "");
  CHECK(f.run("SSTEP") == "*No program to resume*  DEBUG or EXECUTE a program first\n    SSTEP\n");
  // With arguments, as EXECUTE takes them: the monitor's helper program is not stepped.
  CHECK(f.run("DEBUG inner(4)") == "inner, step 1:  v = v + 1\n");
  CHECK(f.run("SSTEP") == "inner, step 2:  v = v * 10\n");
  CHECK(f.run("SSTEP") == "Program completed: inner\n");
}

}  // namespace asimov::test
