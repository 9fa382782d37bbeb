// Ctrl-C inside a motion (Limits::interrupt, read by the simulator before each checked pose):
// the run stops with *Program interrupted* at the motion instruction, the arm where it was;
// PROCEED / RETRY carry out the rest of the motion, then re-run the step that waited for it.
// The flag is set from the simulator's pose hook after N checked poses (deterministic).
#include "asimov/interpreter/monitor.hpp"
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <streambuf>

using namespace asimov;
using interpreter::RunStatus;
using test::InterpreterFixture;

namespace {

// Sets `flag` at the n-th checked pose found free, once.
struct FlagAfter {
  std::atomic<bool> flag{false};
  int n = 0, seen = 0;
  void attach(motion::Simulator& sim, interpreter::Interpreter& interp) {
    interp.limits().interrupt = &flag;
    sim.set_pose_hook([this](double, const robots::JointVector&) {
      if (++seen == n) flag.store(true, std::memory_order_relaxed);
    });
  }
  void again(int after) { n = seen + after; }
};

robots::JointVector jv6(double a, double b, double c, double d, double e, double f) {
  robots::JointVector q(6);
  q << a, b, c, d, e, f;
  return q;
}

const robots::JointVector kReady = jv6(0, -90, 90, 0, 0, 0);
const robots::JointVector kFar = jv6(60, -45, 150, 20, 40, 30);

bool passed_through(const motion::Simulator& sim, const robots::JointVector& q) {
  return std::any_of(sim.recorders().trace.samples.begin(), sim.recorders().trace.samples.end(), [&](const auto& s) { return (s.joints - q).norm() == 0; });
}

// Closest traced joints to q [deg]: after PROCEED the rest of the halted motion blends into the
// next one (continuous path), so the arm rounds q instead of stopping there.
double closest_to(const motion::Simulator& sim, const robots::JointVector& q) {
  double d = 1e300;
  for (const auto& s : sim.recorders().trace.samples) d = std::min(d, (s.joints - q).norm());
  return d;
}

constexpr const char* kProgram = R"(.PROGRAM main()
  MOVE #PPOINT(60, -45, 150, 20, 40, 30)
  TYPE "after"
  MOVE #PPOINT(0, -90, 90, 0, 0, 0)
  TYPE "end"
.END
)";

// Counts the poses of the first motion alone, to rest, so that N can be in it (kProgram blends
// it into the second, docs/blending.md, from near its end on: N = half of these is before).
int first_motion_poses() {
  InterpreterFixture f;
  f.sim.recorders().trace.on = true;
  REQUIRE(f.load(".PROGRAM main()\n  MOVE #PPOINT(60, -45, 150, 20, 40, 30)\n.END\n").empty());
  REQUIRE(f.interp.run("main").status == RunStatus::completed);
  const auto& tr = f.sim.recorders().trace.samples;
  const auto it = std::find_if(tr.begin(), tr.end(), [](const auto& s) { return (s.joints - kFar).norm() == 0; });
  REQUIRE(it != tr.end());
  return static_cast<int>(it - tr.begin()) + 1;
}

}  // namespace

TEST_CASE("Ctrl-C inside a motion halts the arm there and PROCEED finishes the motion then the step", "[interpreter][resume][interrupt]") {
  const int poses = first_motion_poses();
  REQUIRE(poses >= 4);
  for (const bool retry : {false, true}) {
    INFO((retry ? "RETRY" : "PROCEED"));
    InterpreterFixture f;
    f.sim.recorders().trace.on = true;
    FlagAfter stop;
    stop.n = poses / 2;
    stop.attach(f.sim, f.interp);
    REQUIRE(f.load(kProgram).empty());
    auto r = f.interp.run("main");
    REQUIRE(r.status == RunStatus::interrupted);
    CHECK(r.error.message == "*Program interrupted*");
    // Reported at the motion instruction, as a contact is; the TYPE after it had run.
    CHECK(r.error.program == "main");
    CHECK(r.step == 1);
    CHECK(r.error.line == 2);
    CHECK(f.out.str() == "after\n");
    REQUIRE(r.interrupt.has_value());
    CHECK(r.interrupt->step == 1);
    CHECK(r.interrupt->path_fraction > 0);
    CHECK(r.interrupt->path_fraction < 1);
    CHECK(r.interrupt->time_s == f.sim.time_s());
    CHECK((r.interrupt->joints - f.sim.joints()).norm() == 0);
    CHECK((f.sim.joints() - kReady).norm() > 1);
    CHECK((f.sim.joints() - kFar).norm() > 1);
    CHECK(f.sim.recorders().counts.poses == static_cast<std::uint64_t>(stop.n));
    CHECK(closest_to(f.sim, kFar) > 40);  // half way
    CHECK_FALSE(passed_through(f.sim, kFar));
    REQUIRE(f.interp.can_resume());

    stop.flag = false;
    const double t_halt = f.sim.time_s();
    r = retry ? f.interp.retry() : f.interp.proceed();
    INFO(interpreter::format_diagnostic(r.error));
    CHECK(r.status == RunStatus::completed);
    CHECK_FALSE(r.interrupt.has_value());
    // The rest of the first motion ran (rounding its target into the second: the halt was half
    // way, ~50 deg from it), then the second; TYPE "after" did not run again.
    CHECK(closest_to(f.sim, kFar) < 20);  // 10.3 deg: the blend's rounding in joint space
    CHECK((f.sim.joints() - kReady).norm() == 0);
    CHECK(f.sim.time_s() > t_halt);
    CHECK(f.out.str() == "after\nend\n");
    CHECK_FALSE(f.interp.can_resume());
  }
}

TEST_CASE("Ctrl-C in the last motion at the end of the run is resumable", "[interpreter][resume][interrupt]") {
  InterpreterFixture f;
  FlagAfter stop;
  stop.n = 3;
  stop.attach(f.sim, f.interp);
  REQUIRE(f.load(".PROGRAM main()\n  TYPE \"go\"\n  MOVE #PPOINT(60, -45, 150, 20, 40, 30)\n.END\n").empty());
  auto r = f.interp.run("main");
  REQUIRE(r.error.message == "*Program interrupted*");
  CHECK(r.step == 2);
  REQUIRE(r.interrupt.has_value());
  REQUIRE(f.interp.can_resume());
  stop.flag = false;
  r = f.interp.proceed();
  CHECK(r.status == RunStatus::completed);
  CHECK((f.sim.joints() - kFar).norm() == 0);
  CHECK(f.out.str() == "go\n");
}

namespace {
// An output stream that sets the flag when TYPE writes `trigger`: Ctrl-C between two steps.
struct FlagOnText : std::stringbuf {
  std::atomic<bool>* flag = nullptr;
  std::string trigger;
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (std::string_view(s, static_cast<std::size_t>(n)).find(trigger) != std::string_view::npos) flag->store(true);
    return std::stringbuf::xsputn(s, n);
  }
};
}  // namespace

TEST_CASE("Ctrl-C between steps stops a started motion at its start and PROCEED carries it out", "[interpreter][resume][interrupt]") {
  motion::Simulator sim{test::empty_puma_cell()};
  std::atomic<bool> flag{false};
  FlagOnText buf;
  buf.flag = &flag;
  buf.trigger = "x";
  std::ostream out(&buf);
  interpreter::Interpreter interp(sim, out);
  interp.limits().interrupt = &flag;
  REQUIRE(interp.load_source(".PROGRAM main()\n  MOVE #PPOINT(60, -45, 150, 20, 40, 30)\n  TYPE \"x\"\n  TYPE \"y\"\n.END\n",
                             "t.v2").empty());
  auto r = interp.run("main");
  REQUIRE(r.error.message == "*Program interrupted*");
  CHECK(r.step == 3);  // the step not yet run
  REQUIRE(r.interrupt.has_value());
  CHECK(r.interrupt->step == 1);
  CHECK(r.interrupt->path_fraction == 0);  // simulated time had not advanced: still at the start
  CHECK(sim.time_s() == 0);
  CHECK((sim.joints() - kReady).norm() == 0);
  flag = false;
  r = interp.proceed();
  CHECK(r.status == RunStatus::completed);
  CHECK((sim.joints() - kFar).norm() == 0);
  CHECK(buf.str() == "x\ny\n");
}

using asimov::test::MonitorFixture;

TEST_CASE("monitor: Ctrl-C in a motion reports where the arm stopped, then STATUS and PROCEED", "[monitor][interrupt]") {
  const int poses = first_motion_poses();
  MonitorFixture m;
  FlagAfter stop;
  stop.n = poses / 2;
  stop.attach(m.sim, m.interp);
  REQUIRE(m.load(kProgram).empty());
  std::string text = m.run("EXECUTE main");
  INFO(text);
  CHECK(text.rfind("after\n*Program interrupted*\n main, step 1 (test.v2:2)\n", 0) == 0);
  CHECK(text.find("motion halted at t = ") != std::string::npos);
  CHECK(text.find("% of its path\njoints ") != std::string::npos);
  const robots::JointVector halted = m.sim.joints();
  text = m.run("STATUS");
  CHECK(text.find("State: interrupted at step 1, motion of step 1 halted at ") != std::string::npos);

  // A DO that does not move keeps the rest; PROCEED continues from the halted pose.
  stop.flag = false;
  CHECK(m.run("DO TYPE 7") == "7\n");
  REQUIRE(m.sim.halted_motion().has_value());
  CHECK((m.sim.joints() - halted).norm() == 0);
  text = m.run("PROCEED");
  CHECK(text == "end\nProgram completed: main\n");
  CHECK((m.sim.joints() - kReady).norm() == 0);
  CHECK(m.run("STATUS").find("State: completed") != std::string::npos);
}

TEST_CASE("monitor: PROCEED reaches the target after a DO moved the arm or was itself interrupted", "[monitor][interrupt]") {
  const int poses = first_motion_poses();
  MonitorFixture m;
  m.sim.recorders().trace.on = true;
  FlagAfter stop;
  stop.n = poses / 2;
  stop.attach(m.sim, m.interp);
  REQUIRE(m.load(kProgram).empty());
  REQUIRE(m.run("EXECUTE main").find("*Program interrupted*") != std::string::npos);
  stop.flag = false;
  // A DO motion, itself interrupted: its own rest is dropped (a DO is not resumed).
  stop.again(2);
  std::string text = m.run("DO MOVE #PPOINT(-30, -90, 120, 0, 0, 0)");
  INFO(text);
  CHECK(text.rfind("*Program interrupted*\n    DO MOVE", 0) == 0);
  CHECK_FALSE(m.sim.halted_motion().has_value());
  stop.flag = false;
  // PROCEED: the program's motion again, from where the arm is now, then the rest.
  text = m.run("PROCEED");
  CHECK(text == "end\nProgram completed: main\n");
  CHECK(closest_to(m.sim, kFar) < 20);
  CHECK((m.sim.joints() - kReady).norm() == 0);

  // ABORT drops a halted motion with the execution.
  stop.again(3);
  REQUIRE(m.run("EXECUTE main").find("*Program interrupted*") != std::string::npos);
  REQUIRE(m.sim.halted_motion().has_value());
  stop.flag = false;
  m.run("ABORT");
  CHECK_FALSE(m.sim.halted_motion().has_value());
  CHECK(m.run("PROCEED").find("*No program to resume*") != std::string::npos);
}
