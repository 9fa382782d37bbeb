// Programs that move the PUMA 560 in an empty cell: targets reach the simulator, forward
// processing, HERE/DECOMPOSE, SPEED, motion errors, collisions.
#include "support/cell_bodies.hpp"
#include "interpreter_fixture.hpp"
#include "asimov/collision/polyhedron.hpp"
#include "asimov/motion/location.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;
using Catch::Detail::Approx;

namespace {

double distance_mm(const asimov::motion::Location& a, const asimov::motion::Location& b) {
  return (a.translation() - b.translation()).norm();
}

}  // namespace

TEST_CASE("MOVE to a precision point reaches its joints", "[motion]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\n  MOVE #PPOINT(10, -80, 100, 0, 20, 30)\n.END\n");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  const auto& j = f.sim.joints();
  CHECK(j[0] == Approx(10).margin(1e-6));
  CHECK(j[1] == Approx(-80).margin(1e-6));
  CHECK(j[5] == Approx(30).margin(1e-6));
  CHECK(f.sim.time_s() > 0);
  CHECK_FALSE(f.sim.motion_pending());
}

TEST_CASE("SET, MOVE, MOVES, APPRO, DEPART, HERE and DECOMPOSE", "[motion]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  MOVE #PPOINT(10, -60, 150, 10, 40, 20)
  BREAK
  SET start = HERE
  DECOMPOSE s[0] = start
  SET pick = TRANS(s[0], s[1], s[2] - 100, s[3], s[4], s[5])
  MOVE pick
  BREAK
  HERE p1
  DECOMPOSE q[1] = p1
  TYPE /F0.2, q[3] - s[2]
  APPRO pick, 50
  BREAK
  TYPE /F0.2, DISTANCE(HERE, pick)
  MOVES pick
  DEPART 30
  BREAK
  TYPE /F0.2, DISTANCE(HERE, pick)
  SET #j = #PPOINT(15, -60, 150, 10, 40, 20)
  MOVES #j
  HERE #before          ; forward processing: the motion has not run yet
  BREAK
  HERE #now
  TYPE DISTANCE(#before, #now) > 1
  DECOMPOSE jv[0] = #now
  TYPE /F0.2, jv[1], jv[0]
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  const std::string out = f.out.str();
  CHECK(out == "-100.00\n50.00\n30.00\n-1\n-60.0015.00\n");
  CHECK(f.sim.joints()[0] == Approx(15).margin(1e-3));
}

TEST_CASE("DEPART takes HERE after the previous motion ended", "[motion]") {
  InterpreterFixture f;
  REQUIRE(f.run(".PROGRAM work()\n MOVE #PPOINT(10, -60, 150, 10, 40, 20)\n.END\n", "work").status == RunStatus::completed);
  const auto ready = f.sim.here();
  const auto r = f.run(R"(.PROGRAM main()
  SET a = HERE:TRANS(0, 0, 80)
  MOVE a
  DEPART 80
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(distance_mm(f.sim.here(), ready) == Approx(0).margin(1e-3));
}

TEST_CASE("APPRO backs off along the target's tool Z", "[motion]") {
  InterpreterFixture f;
  REQUIRE(f.run(".PROGRAM work()\n MOVE #PPOINT(10, -60, 150, 10, 40, 20)\n.END\n", "work").status == RunStatus::completed);
  const auto ready = f.sim.here();
  const auto r = f.run(".PROGRAM main()\n  SET a = HERE\n  APPRO a, 40\n.END\n");
  INFO(asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  const auto expected = ready * asimov::motion::trans(0, 0, -40, 0, 0, 0);
  CHECK(distance_mm(f.sim.here(), expected) == Approx(0).margin(1e-3));
}

TEST_CASE("forward processing: the motion runs at the next motion, BREAK or the end", "[motion]") {
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM main()\n  MOVE #PPOINT(20, -90, 90, 0, 0, 0)\n  TYPE DZ(HERE) > 0\n.END\n").empty());
  const double t0 = f.sim.time_s();
  const auto start = f.sim.here();
  const auto r = f.interp.run("main");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.sim.time_s() > t0);
  CHECK(distance_mm(f.sim.here(), start) > 1);
}

TEST_CASE("SPEED applies to the next motion only unless ALWAYS", "[motion]") {
  auto duration = [](const std::string& body) {
    InterpreterFixture f;
    const auto r = f.run(".PROGRAM main()\n" + body + "\n.END\n");
    INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
    REQUIRE(r.status == RunStatus::completed);
    return f.sim.time_s();
  };
  const std::string moves = "MOVE #PPOINT(60, -90, 90, 0, 0, 0)\nMOVE #PPOINT(0, -90, 90, 0, 0, 0)\n";
  const double fast = duration(moves);
  const double slow_once = duration("SPEED 20\n" + moves);
  const double slow_always = duration("SPEED 20 ALWAYS\n" + moves);
  CHECK(slow_once > fast);
  CHECK(slow_always > slow_once);
  // Each run starts with SPEED 100 ALWAYS.
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM slow()\nSPEED 10 ALWAYS\n.END\n.PROGRAM main()\n" + moves + ".END\n").empty());
  REQUIRE(f.interp.run("slow").status == RunStatus::completed);
  const double t0 = f.sim.time_s();
  REQUIRE(f.interp.run("main").status == RunStatus::completed);
  CHECK(f.sim.time_s() - t0 == Approx(fast).epsilon(1e-6));
}

TEST_CASE("motion errors come from the simulator with the step", "[motion][errors]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\n  x = 1\n  MOVE TRANS(5000, 0, 0)\n.END\n");
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.message == "*Location out of reach*");
  CHECK(r.error.step == 2);
  CHECK(r.error.line == 3);

  InterpreterFixture g;
  const auto s = g.run(".PROGRAM main()\n  MOVE 3\n.END\n");
  REQUIRE(s.status == RunStatus::error);
  CHECK(s.error.message == "*Illegal value*");

  InterpreterFixture h;
  const auto t = h.run(".PROGRAM main()\n  SET #p = #PPOINT(0,0,0,0,0,0)\n  SET q = #p:TRANS(1)\n.END\n");
  REQUIRE(t.status == RunStatus::error);
  CHECK(t.error.message == "*Illegal value*");
}

TEST_CASE("a collision ends the run and names the motion's step", "[motion][collision]") {
  using namespace asimov;
  // Find the tool point halfway through a J1 sweep and put a box there.
  motion::Location work;
  {
    InterpreterFixture probe;
    REQUIRE(probe.run(".PROGRAM work()\n MOVE #PPOINT(25, -60, 150, 10, 40, 20)\n.END\n", "work").status == RunStatus::completed);
    work = probe.sim.here();
  }
  motion::Cell cell = test::empty_puma_cell();
  cell.objects.push_back(test::box_object("box", collision::Vec3(60, 60, 60), work.translation()));
  motion::Simulator sim(cell);
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  REQUIRE(interp.load_source(R"(.PROGRAM main()
  MOVE #PPOINT(10, -60, 150, 10, 40, 20)
  SET #target = #PPOINT(40, -60, 150, 10, 40, 20)
  MOVE #target
  TYPE "typed before the motion runs"
.END
)", "hit.v2").empty());
  const interpreter::RunResult r = interp.run("main");
  INFO(interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::collision);
  CHECK(r.error.message == "*Collision*");
  CHECK(r.error.detail.find("box") != std::string::npos);
  CHECK(r.error.detail.find(" / ") != std::string::npos);
  CHECK(r.error.program == "main");
  CHECK(r.error.step == 3);  // MOVES, although the contact is found at the program's end
  CHECK(r.error.line == 4);
  CHECK(r.step == 3);
  CHECK(r.collision.step == 3);
  CHECK((r.collision.body_a == "box" || r.collision.body_b == "box"));
  CHECK(out.str() == "typed before the motion runs\n");

  // RETRY restarts the interrupted motion from the halted pose: it meets the box again.
  REQUIRE(interp.can_resume());
  const interpreter::RunResult again = interp.retry();
  CHECK(again.status == RunStatus::collision);
  CHECK(again.error.step == 3);
  // PROCEED drops it; contact was found at the program's end, so nothing is left to run.
  const interpreter::RunResult done = interp.proceed();
  CHECK(done.status == RunStatus::completed);
  CHECK_FALSE(interp.can_resume());
}

TEST_CASE("READY, DRAW, TOOL, BASE and configuration words", "[motion]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  MOVE #PPOINT(10, -60, 150, 10, 40, 20)
  BREAK
  SET start = HERE
  DRAW 0, , 30
  BREAK
  TYPE /F0.2, DZ(HERE) - DZ(start), DX(HERE) - DX(start)
  TOOL TRANS(0, 0, 100)
  TYPE /F0.2, DISTANCE(HERE, start) > 50
  TOOL
  BASE 0, 0, 100
  TYPE /F0.2, DZ(BASE)
  BASE NULL
  LEFTY
  BELOW
  FLIP
  MULTIPLE
  RIGHTY
  ABOVE
  NOFLIP
  SINGLE
  READY
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "30.000.00\n-1.00\n100.00\n");
  CHECK(f.sim.joints()[1] == Approx(-90).margin(1e-6));
  CHECK(f.sim.joints()[2] == Approx(90).margin(1e-6));
  CHECK(f.sim.settings().request.righty == 1);
  CHECK(f.sim.settings().request.single);
}

TEST_CASE("ALIGN turns tool Z onto the nearest world axis, DRIVE moves one joint", "[motion]") {
  InterpreterFixture f;
  const auto r = f.run(R"(.PROGRAM main()
  MOVE #PPOINT(10, -60, 150, 10, 40, 20)
  BREAK
  SET before = HERE
  ALIGN
  BREAK
  SET after = HERE
  TYPE /F0.3, DISTANCE(before, after)
.END
)");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "0.000\n");  // the tool point stays
  const Eigen::Vector3d z = f.sim.here().linear().col(2);
  CHECK(z.cwiseAbs().maxCoeff() == Approx(1).margin(1e-6));
  const double j1 = f.sim.joints()[0], j2 = f.sim.joints()[1];
  REQUIRE(f.run(".PROGRAM turn()\n  DRIVE 1, -15, 50\n.END\n", "turn").status == RunStatus::completed);
  CHECK(f.sim.joints()[0] == Approx(j1 - 15).margin(1e-9));
  CHECK(f.sim.joints()[1] == Approx(j2).margin(1e-9));

  InterpreterFixture g;
  const auto s = g.run(".PROGRAM main()\n  DRIVE 7, 10, 50\n.END\n");
  CHECK(s.error.message == "*Illegal value*");
}

TEST_CASE("RunResult::motions: each motion instruction started, with its step, program and line", "[motion]") {
  InterpreterFixture f;
  // Both programs have a motion at step 1; a loop starts the same MOVE twice.
  const auto r = f.run(".PROGRAM main()\n  MOVE #PPOINT(0, -90, 90, 0, 0, 0)\n  CALL sub()\n"
                       "  FOR i = 1 TO 2\n    MOVE #PPOINT(10, -80, 100, 0, 20, 30)\n  END\n.END\n"
                       ".PROGRAM sub()\n  READY\n.END\n");
  INFO(f.load_report << asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  REQUIRE(r.motions.size() == 3);
  CHECK(r.motions[0].step == 1);
  CHECK(r.motions[0].program == "main");
  CHECK(r.motions[0].line == 2);
  CHECK(r.motions[0].text == "MOVE #PPOINT(0, -90, 90, 0, 0, 0)");
  CHECK(r.motions[1].step == 1);
  CHECK(r.motions[1].program == "sub");
  CHECK(r.motions[1].line == 9);
  CHECK(r.motions[1].text == "READY");
  CHECK(r.motions[2].step == 4);
  CHECK(r.motions[2].line == 5);
}
