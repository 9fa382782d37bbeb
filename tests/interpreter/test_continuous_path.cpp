// Continuous path in programs (docs/blending.md): with CP on (the default) consecutive motion
// instructions blend; BREAK, DISABLE CP, WAIT, WAIT.EVENT, the immediate hand instructions,
// PAUSE and the end of the program stop the arm; SIGNAL and TYPE between motions do not. The
// run's motion_times list every motion's start, planned duration and whether it blended.
#include "interpreter_fixture.hpp"
#include "asimov/collision/polyhedron.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace asimov;
using interpreter::RunStatus;
using test::InterpreterFixture;

namespace {

constexpr const char* kA = "#PPOINT(30, -60, 120, 0, 30, 0)";
constexpr const char* kB = "#PPOINT(-30, -60, 120, 0, 30, 0)";

// Runs `body` (between two motions) and returns the run's motion times.
std::vector<interpreter::MotionTime> times_with(const std::string& between, double* end_s = nullptr) {
  InterpreterFixture f;
  const auto r = f.run(std::string(".PROGRAM main()\n  MOVE ") + kA + "\n" + between + "  MOVE " + kB + "\n.END\n");
  INFO(f.load_report);
  REQUIRE(f.loaded);
  INFO(interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  if (end_s) *end_s = f.sim.time_s();
  return r.motion_times;
}

}  // namespace

TEST_CASE("CP: consecutive motions blend, the run is the overlap shorter", "[interpreter][blend]") {
  double blended_end = 0, stopped_end = 0;
  const auto blended = times_with("", &blended_end);
  const auto stopped = times_with("  BREAK\n", &stopped_end);
  REQUIRE(blended.size() == 2);
  REQUIRE(stopped.size() == 2);
  CHECK_FALSE(blended[0].blended);
  CHECK(blended[1].blended);
  CHECK(blended[1].step == 2);
  CHECK(blended[1].program == "main");
  CHECK(blended[1].start_s < blended[0].start_s + blended[0].duration_s);  // it overlaps
  CHECK_FALSE(stopped[1].blended);
  CHECK(stopped[1].start_s == Approx(stopped[0].start_s + stopped[0].duration_s));
  // Same motions, same durations; only the start of the second moves.
  CHECK(blended[1].duration_s == Approx(stopped[1].duration_s));
  const double overlap = stopped[1].start_s - blended[1].start_s;
  CHECK(overlap > 0);
  CHECK(blended_end == Approx(stopped_end - overlap));
  CHECK(blended_end == Approx(blended[1].start_s + blended[1].duration_s));
}

TEST_CASE("CP: what forces a stop between two motions and what does not", "[interpreter][blend]") {
  for (const char* stop : {"  BREAK\n", "  DISABLE CP\n", "  WAIT\n", "  WAIT.EVENT , 0\n", "  OPENI\n", "  CLOSEI\n",
                           "  RELAXI\n"}) {
    INFO(stop);
    const auto t = times_with(stop);
    REQUIRE(t.size() == 2);
    CHECK_FALSE(t[1].blended);
    CHECK(t[1].start_s >= t[0].start_s + t[0].duration_s);
  }
  for (const char* go_on : {"  SIGNAL 1\n", "  TYPE \"x\"\n", "  x = 1\n", "  OPEN\n", "  SPEED 50\n", "  ENABLE CP\n"}) {
    INFO(go_on);
    const auto t = times_with(go_on);
    REQUIRE(t.size() == 2);
    CHECK(t[1].blended);
  }
}

TEST_CASE("CP: SWITCH(CP) follows ENABLE / DISABLE CP, on by default", "[interpreter][blend]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\n  TYPE SWITCH(CP)\n  DISABLE CP\n  TYPE SWITCH(CP)\n  ENABLE CP\n  TYPE SWITCH(CP)\n.END\n");
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "-1\n0\n-1\n");
}

TEST_CASE("CP: a relative motion after a pending one starts from its target and ends where the stopped one does",
          "[interpreter][blend]") {
  for (const char* relative : {"DEPART 50", "DEPARTS 50", "DRAW 10, 20, 30", "DRIVE 1, 10, 50", "ALIGN"}) {
    INFO(relative);
    const std::string program = std::string(".PROGRAM main()\n  MOVE ") + kA + "\n%  " + relative + "\n.END\n";
    auto with = [&](const std::string& between) {
      std::string p = program;
      p.replace(p.find('%'), 1, between);
      InterpreterFixture f;
      const auto r = f.run(p);
      INFO(f.load_report << interpreter::format_diagnostic(r.error));
      REQUIRE(r.status == RunStatus::completed);
      REQUIRE(r.motion_times.size() == 2);
      return std::pair{f.sim.joints(), r.motion_times[1].blended};
    };
    const auto [blended_q, blended] = with("");
    const auto [stopped_q, stopped] = with("  BREAK\n");
    CHECK(blended);
    CHECK_FALSE(stopped);
    CHECK((blended_q - stopped_q).norm() < 1e-9);
  }
}

TEST_CASE("CP: a contact is reported at the motion whose path met it, not the one that carried it out",
          "[interpreter][blend]") {
  // A box on the sweep of the second MOVE about J1 (its flange point half way): the third MOVE
  // starts the walk of the second up to the blend, which meets the box; the report names the
  // second MOVE (step 3), the TYPE before the third has run.
  motion::Cell cell = test::empty_puma_cell();
  robots::JointVector mid(6);
  mid << 10, -20, 169, 90, -90, 0;
  motion::CellObject box;
  box.name = "box";
  box.mesh = collision::make_box({80, 80, 80});
  box.pose = motion::Location::Identity();
  box.pose.translation() = robots::flange_pose(cell.robot, mid).translation();
  cell.objects.push_back(box);
  motion::Simulator sim(cell);
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  REQUIRE(interp.load_source(".PROGRAM main()\n  MOVE #PPOINT(-40, -20, 169, 90, -90, 0)\n  BREAK\n"
                             "  MOVE #PPOINT(60, -20, 169, 90, -90, 0)\n  TYPE \"between\"\n"
                             "  MOVE #PPOINT(60, -60, 120, 0, 30, 0)\n.END\n",
                             "t.v2")
              .empty());
  const auto r = interp.run("main");
  REQUIRE(r.status == RunStatus::collision);
  CHECK(r.collision.step == 3);
  CHECK(r.line == 4);
  CHECK(r.error.line == 4);
  CHECK(out.str() == "between\n");
  CHECK(r.collision.joints[0] < 10);  // on the way to the box, before the blend
}

TEST_CASE("ACCEL: acceleration and deceleration percentages lengthen the motion, omitted values are kept",
          "[interpreter][blend][accel]") {
  auto duration = [](const std::string& accel) {
    InterpreterFixture f;
    const auto r = f.run(std::string(".PROGRAM main()\n") + accel + "\n  MOVE " + kA + "\n.END\n");
    INFO(f.load_report << interpreter::format_diagnostic(r.error));
    REQUIRE(r.status == RunStatus::completed);
    REQUIRE(r.motion_times.size() == 1);
    return r.motion_times[0].duration_s;
  };
  const double full = duration("");
  CHECK(duration("  ACCEL (1) 100, 100") == Approx(full).epsilon(1e-12));  // Adept's drivers' line
  CHECK(duration("  ACCEL 500, 200") == Approx(full).epsilon(1e-12));      // above 100: 100
  const double half = duration("  ACCEL 50, 50");
  CHECK(half > full);
  const double accel_only = duration("  ACCEL 50");
  CHECK(accel_only > full);
  CHECK(accel_only < half);
  CHECK(duration("  ACCEL , 50") == Approx(accel_only).epsilon(1e-9));  // the ramps are symmetric in time
  CHECK(duration("  ACCEL 50\n  ACCEL , 50") == Approx(half).epsilon(1e-12));  // the first value kept
  CHECK(duration("  ACCEL 0, 0") > half);  // below 1: 1 %
}

TEST_CASE("ACCEL: a lower deceleration lengthens the blend with the next motion", "[interpreter][blend][accel]") {
  auto overlap = [](const std::string& accel) {
    InterpreterFixture f;
    const auto r = f.run(std::string(".PROGRAM main()\n") + accel + "\n  MOVE " + kA + "\n  MOVE " + kB + "\n.END\n");
    REQUIRE(r.status == RunStatus::completed);
    REQUIRE(r.motion_times.size() == 2);
    CHECK(r.motion_times[1].blended);
    return r.motion_times[0].start_s + r.motion_times[0].duration_s - r.motion_times[1].start_s;
  };
  // tau = min(deceleration of the first, acceleration of the second): both ramps longer at 50 %.
  const double base = overlap("");
  CHECK(base > 0);
  CHECK(overlap("  ACCEL 50, 50") > base * 1.4);  // x 2 (trapezoid) or x sqrt 2 (triangle)
}

TEST_CASE("ACCEL: too many values is a load error", "[interpreter][accel]") {
  InterpreterFixture f;
  const auto d = f.load(".PROGRAM main()\n  ACCEL 1, 2, 3\n.END\n");
  REQUIRE(!d.empty());
  CHECK(interpreter::format_diagnostic(d[0]).find("ACCEL expects") != std::string::npos);
}

TEST_CASE("CP with tasks: the robot task blends while a logic task runs, the same on every run",
          "[interpreter][blend][tasks]") {
  const std::string robot = std::string("  MOVE ") + kA + "\n  MOVE " + kB + "\n  MOVE " + kA + "\n  BREAK\n";
  const std::string logic = std::string(".PROGRAM main()\n  done = 0\n  n = 0\n  seen = 0\n  EXECUTE 1 logic()\n") +
                            robot + "  done = 1\n  CYCLE.END 1\n  TYPE n, \" \", seen, \" \", SIG(2010)\n.END\n"
                            ".PROGRAM logic()\n  WHILE done == 0 DO\n    n = n + 1\n"
                            "    IF STATE(2) == 1 THEN\n      seen = seen + 1\n      SIGNAL 2010\n    END\n"
                            "    WAIT\n  END\n.END\n";
  struct Outcome {
    std::string out;
    std::vector<interpreter::MotionTime> times;
    double end_s;
  };
  auto run = [](const std::string& text) {
    InterpreterFixture f;
    const auto r = f.run(text);
    INFO(f.load_report << interpreter::format_diagnostic(r.error));
    REQUIRE(r.status == RunStatus::completed);
    return Outcome{f.out.str(), r.motion_times, f.sim.time_s()};
  };
  const Outcome a = run(logic), b = run(logic);
  const Outcome alone = run(".PROGRAM main()\n" + robot + ".END\n");
  REQUIRE(a.times.size() == 3);
  CHECK_FALSE(a.times[0].blended);
  CHECK(a.times[1].blended);
  CHECK(a.times[2].blended);
  // The logic task changes nothing of the arm's path or timing, bit for bit.
  REQUIRE(alone.times.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(a.times[i].start_s == alone.times[i].start_s);
    CHECK(a.times[i].duration_s == alone.times[i].duration_s);
    CHECK(a.times[i].start_s == b.times[i].start_s);
  }
  // The logic task ticked (16 ms) through the whole motion and saw the arm moving every time;
  // at the first tick after the motion's end the robot task has set done.
  CHECK(a.out == b.out);
  CHECK(a.end_s == b.end_s);
  const double motion_end = alone.end_s;
  const int ticks = static_cast<int>(std::ceil(motion_end / 0.016));
  CHECK(a.out == std::to_string(ticks) + " " + std::to_string(ticks) + " -1\n");
}

TEST_CASE("#PDEST: the joints the pending motion ends at, at rest the arm's joints", "[interpreter][blend][pdest]") {
  InterpreterFixture f;
  const std::string text = std::string(".PROGRAM main()\n  SET #s = #PDEST\n  MOVE ") + kA +
                           "\n  SET #a = #pdest\n  MOVE " + kB + "\n  SET #b = #PDEST\n  BREAK\n  SET #r = #PDEST\n"
                           "  DECOMPOSE s[0] = #s\n  DECOMPOSE a[0] = #a\n  DECOMPOSE b[0] = #b\n  DECOMPOSE r[0] = #r\n"
                           "  TYPE s[0], s[1], s[2], \"|\", a[0], a[1], a[2], a[4], \"|\", b[0], \"|\", r[0]\n"
                           "  TYPE DISTANCE(#PDEST, HERE)\n.END\n";
  CHECK(test::outcome_of(f, text) == "0 -90 90|30 -60 120 30|-30|-30\n0\n");
  // check knows #PDEST: a precision point, no load error or warning.
  InterpreterFixture g;
  CHECK(g.load(".PROGRAM main()\n  SET #x = #PDEST\n  MOVE #PDEST\n.END\n").empty());
  const auto d = g.load(".PROGRAM main()\n  SET x = #PDEST\n.END\n");  // as #PPOINT: a '#' variable only
  REQUIRE(d.size() == 1);
  CHECK(interpreter::format_diagnostic(d[0]).find("x cannot hold a precision point") != std::string::npos);
  CHECK(test::outcome_of(g, ".PROGRAM main()\n  SET #x = #PDEST()\n  MOVE #x\n  TYPE \"ok\"\n.END\n") == "ok\n");
}

TEST_CASE("#PDEST in a second task: the motion in progress at the task's time", "[interpreter][blend][pdest][tasks]") {
  // The probe samples J1 of #PDEST at every tick: 30 (A) while the first motion runs, -30 (B)
  // once the second has started (blending: before the first has ended), and after it.
  InterpreterFixture f;
  const std::string text = std::string(".PROGRAM main()\n  done = 0\n  k = 0\n  EXECUTE 1 probe()\n  MOVE ") + kA +
                           "\n  MOVE " + kB + "\n  BREAK\n  WAIT.EVENT , 0.05\n  done = 1\n  CYCLE.END 1\n"
                           "  FOR i = 1 TO k\n    TYPE t[i], \" \", j[i]\n  END\n.END\n"
                           ".PROGRAM probe()\n  WHILE done == 0 DO\n    DECOMPOSE q[0] = #PDEST\n    k = k + 1\n"
                           "    t[k] = TIMER(0)\n    j[k] = q[0]\n    WAIT\n  END\n.END\n";
  const auto r = f.run(text);
  INFO(f.load_report << interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  REQUIRE(r.motion_times.size() == 2);
  REQUIRE(r.motion_times[1].blended);
  const double b_start = r.motion_times[1].start_s;
  std::istringstream lines(f.out.str());
  int before = 0, after = 0;
  for (double t = 0, j1 = 0; lines >> t >> j1;) {
    INFO("t = " << t);
    if (t < b_start) {
      CHECK(j1 == 30);
      ++before;
    } else {
      CHECK(j1 == -30);
      ++after;
    }
  }
  CHECK(before > 10);
  CHECK(after > 10);
}

TEST_CASE("CP: DURATION lengthens both motions and they still blend", "[interpreter][blend]") {
  const auto plain = times_with("");
  const auto slow = times_with("  DURATION 2 ALWAYS\n");  // the second motion only
  REQUIRE(slow.size() == 2);
  CHECK(slow[1].blended);
  CHECK(slow[1].duration_s == Approx(2).epsilon(1e-9));
  CHECK(slow[1].duration_s > plain[1].duration_s);
  CHECK(slow[0].duration_s == plain[0].duration_s);
  CHECK(slow[1].start_s < slow[0].start_s + slow[0].duration_s);
}

TEST_CASE("CP: the end of the program and an error leave the last motion ended at rest at its target",
          "[interpreter][blend]") {
  robots::JointVector b(6);
  b << -30, -60, 120, 0, 30, 0;
  for (const char* end : {"", "  x = 1 / 0\n", "  TYPE y\n"}) {
    INFO(end);
    InterpreterFixture f;
    const auto r = f.run(std::string(".PROGRAM main()\n  MOVE ") + kA + "\n  MOVE " + kB + "\n" + end + ".END\n");
    REQUIRE(f.loaded);
    CHECK(r.status == (*end ? RunStatus::error : RunStatus::completed));
    REQUIRE(r.motion_times.size() == 2);
    CHECK(r.motion_times[1].blended);
    CHECK_FALSE(f.sim.motion_pending());
    CHECK(f.sim.time_s() == Approx(r.motion_times[1].start_s + r.motion_times[1].duration_s).epsilon(1e-12));
    CHECK((f.sim.joints() - b).norm() < 1e-9);
  }
}
