// Tasks (dialect §7b): EXECUTE, cooperative scheduling on the simulated clock, the robot task,
// LOCAL per task, ABORT / CYCLE.END / RELEASE, time slices, determinism.
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;

namespace {

std::string outcome(const std::string& programs, InterpreterFixture& f) { return asimov::test::outcome_of(f, programs); }

std::string outcome(const std::string& programs) {
  InterpreterFixture f;
  return outcome(programs, f);
}

}  // namespace

TEST_CASE("tasks run by their wake times on the simulated clock", "[tasks]") {
  const std::string text = ".PROGRAM main()\n  TIMER 1 = 0\n  EXECUTE 1 ticker()\n  WAIT.EVENT , 0.05\n"
                           "  TYPE \"main \", TIMER(1)\n  CYCLE.END 1\n  TYPE \"main end \", TIMER(1)\n.END\n"
                           ".PROGRAM ticker()\n  FOR i = 1 TO 3\n    TYPE \"tick \", i, \" \", TIMER(1)\n"
                           "    WAIT.EVENT , 0.02\n  END\n.END\n";
  InterpreterFixture f;
  CHECK(outcome(text, f) == "tick 1 0\ntick 2 0.02\ntick 3 0.04\nmain 0.05\nmain end 0.066\n");
  CHECK(f.sim.time_s() == Approx(0.066));
  const auto r = f.interp.run("main");
  REQUIRE(r.tasks.size() == 2);
  CHECK(r.tasks[0].number == 0);
  CHECK(r.tasks[0].program == "main");
  CHECK(r.tasks[1].program == "ticker");
  CHECK(r.tasks[1].state == "completed");
}

TEST_CASE("LOCAL variables belong to the task, GLOBALs are shared, RELEASE gives way", "[tasks]") {
  CHECK(outcome(".PROGRAM main()\n  shared = 0\n  EXECUTE 1 count(1)\n  EXECUTE 2 count(2)\n  CYCLE.END 1\n"
                "  CYCLE.END 2\n  TYPE shared\n.END\n"
                ".PROGRAM count(id)\n  LOCAL mine, i\n  mine = 0\n  FOR i = 1 TO 5\n    mine = mine + id\n"
                "    shared = shared + 1\n    RELEASE\n  END\n  TYPE \"task \", TASK(), \" mine \", mine\n.END\n")
        == "task 1 mine 5\ntask 2 mine 10\n10\n");
}

TEST_CASE("only the robot task moves the arm", "[tasks]") {
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 1 mover()\n  WAIT.EVENT , 0.1\n.END\n"
                ".PROGRAM mover()\n  MOVE #PPOINT(10, -90, 90, 0, 0, 0)\n.END\n")
        == "ERROR *Robot not attached to this program* task 1");
  // DETACH () gives the robot away; another task may ATTACH () it.
  CHECK(outcome(".PROGRAM main()\n  DETACH ()\n  EXECUTE 1 mover()\n  CYCLE.END 1\n  TYPE DX(HERE) <> 0\n.END\n"
                ".PROGRAM mover()\n  ATTACH ()\n  MOVE #PPOINT(10, -90, 90, 0, 0, 0)\n  BREAK\n  TYPE \"moved\"\n.END\n")
        == "moved\n-1\n");
}

TEST_CASE("other tasks run while the arm moves, the robot task waits for its motion", "[tasks][motion]") {
  InterpreterFixture f;
  const std::string out = outcome(".PROGRAM main()\n  moving = 1\n  n = 0\n  seen = 0\n  EXECUTE 2 watch()\n"
                                  "  MOVE #PPOINT(60, -90, 90, 0, 0, 0)\n  BREAK\n  moving = 0\n  CYCLE.END 2\n"
                                  "  TYPE n, seen\n.END\n"
                                  ".PROGRAM watch()\n  WHILE moving DO\n    n = n + 1\n    IF STATE(2) == 1 THEN\n"
                                  "      seen = seen + 1\n    END\n    WAIT\n  END\n.END\n", f);
  // The run ends one tick after the motion (CYCLE.END polls once more); it started at 0.
  const double t = f.sim.time_s() - 0.016;
  REQUIRE(t > 0.1);
  const int ticks = static_cast<int>(std::ceil(t / 0.016));
  CHECK(out == std::to_string(ticks) + " " + std::to_string(ticks) + "\n");
}

TEST_CASE("ABORT ends a task, TASK(1, n) says whether it executes", "[tasks]") {
  InterpreterFixture f;
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 1 forever()\n  WAIT.EVENT , 0.1\n  TYPE TASK(1, 1)\n  ABORT 1\n"
                "  TYPE TASK(1, 1), TASK(1, 3)\n.END\n.PROGRAM forever()\n  WHILE TRUE DO\n    WAIT\n  END\n.END\n", f)
        == "4\n0 0\n");
  const auto r = f.interp.run("main");
  REQUIRE(r.tasks.size() == 2);
  CHECK(r.tasks[1].state == "aborted");
}

TEST_CASE("a task that never gives way still lets the others run (time slices)", "[tasks]") {
  CHECK(outcome(".PROGRAM main()\n  halt.busy = 0\n  EXECUTE 1 busy()\n  WAIT.EVENT , 0.01\n  halt.busy = 1\n"
                "  CYCLE.END 1\n  TYPE n > 1000\n.END\n"
                ".PROGRAM busy()\n  n = 0\n  WHILE NOT halt.busy DO\n    n = n + 1\n  END\n.END\n")
        == "-1\n");
}

TEST_CASE("EXECUTE errors: a task already executing, an absent program, a bad number", "[tasks]") {
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 1 w()\n  EXECUTE 1 w()\n.END\n.PROGRAM w()\n  WAIT.EVENT , 1\n.END\n")
        == "ERROR *Illegal value* task 1 is executing");
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 3 nothing()\n.END\n") == "ERROR *Undefined program or variable name* nothing");
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 99 main()\n.END\n") == "ERROR *Illegal value* task 99");
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 0 main()\n.END\n") == "ERROR *Illegal value* task 0 is executing");
  // An error in another task stops the run, located there.
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\n  EXECUTE 1 bad()\n  WAIT.EVENT , 1\n.END\n.PROGRAM bad()\n  x = 1 / 0\n.END\n");
  CHECK(r.error.message == "*Division by zero*");
  CHECK(r.program == "bad");
  CHECK_FALSE(f.interp.can_resume());
}

TEST_CASE("the same programs give the same output and times on every run", "[tasks]") {
  const std::string text = ".PROGRAM main()\n  EXECUTE 1 plc()\n  FOR k = 1 TO 2\n"
                           "    MOVE #PPOINT(30 * k, -90, 90, 0, 0, 0)\n    BREAK\n    SIGNAL 2001\n"
                           "    WAIT SIG(2002)\n    SIGNAL -2001\n    WAIT SIG(-2002)\n  END\n.END\n"
                           ".PROGRAM plc()\n  LOCAL k\n  FOR k = 1 TO 2\n    WAIT SIG(2001)\n    WAIT.EVENT , 0.25\n"
                           "    TYPE \"clamped \", k\n    SIGNAL 2002\n    WAIT SIG(-2001)\n    SIGNAL -2002\n  END\n.END\n";
  InterpreterFixture a, b;
  const std::string out = outcome(text, a);
  CHECK(out == "clamped 1\nclamped 2\n");
  CHECK(outcome(text, b) == out);
  CHECK(a.sim.time_s() == b.sim.time_s());
  CHECK(a.sim.recorders().counts.poses == b.sim.recorders().counts.poses);
}

TEST_CASE("EXECUTE and TAS parse as V+ writes them", "[tasks]") {
  InterpreterFixture f;
  CHECK(f.load(".PROGRAM a()\n  EXECUTE 1 b.c()\n  EXECUTE b.c\n  EXECUTE /C 2 b.c(1, 2), 1\n  x = TAS(y, 1)\n.END\n"
               ".PROGRAM b.c(p, q)\n.END\n").empty());
  CHECK(outcome(".PROGRAM main()\n  y = 5\n  TYPE TAS(y, 7), y, TAS(z, 1), z\n.END\n") == "5 7 0 1\n");
}

TEST_CASE("STATUS lists the tasks of the last execution", "[monitor][tasks]") {
  asimov::test::MonitorFixture f;
  REQUIRE(f.load(".PROGRAM main()\n  EXECUTE 1 helper()\n  CYCLE.END 1\n.END\n.PROGRAM helper()\n  WAIT.EVENT , 0.1\n.END\n")
              .empty());
  f.run("EXECUTE main");
  const std::string status = f.run("STATUS");
  CHECK(status.find("Tasks:\n") != std::string::npos);
  CHECK(status.find("   0  main             completed\n") != std::string::npos);
  CHECK(status.find("   1  helper           completed\n") != std::string::npos);
}
