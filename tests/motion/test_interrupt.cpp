// Ctrl-C inside a motion (Simulator::set_interrupt): the arm stops at the last checked pose,
// the clock at that pose's time, and resume_motion carries out the rest of the same path. The
// flag is set from the pose hook after N checked poses, so every run is deterministic.
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"
#include "support/joints.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;
using test::jv;

namespace {

Cell cell_with(Stepping stepping, bool collision = true) {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = jv({0, -90, 90, 0, 0, 0});
  c.collision.step_mm = 2.0;
  c.collision.stepping = stepping;
  c.collision.enabled = collision;
  // A box well away from the paths below: a robot-object pair, so gap stepping has gaps to use.
  c.objects.push_back(test::box_object("crate", {200, 200, 200}, {-700, 0, -300}));
  return c;
}

// Sets `flag` at the n-th checked pose found free.
struct FlagAfter {
  std::atomic<bool> flag{false};
  int n = 0, seen = 0;
  void attach(Simulator& sim) {
    sim.set_interrupt(&flag);
    sim.set_pose_hook([this](double, const JointVector&) {
      if (++seen == n) flag.store(true, std::memory_order_relaxed);
    });
  }
};

// Distance of q from the joint-space segment a-b (a joint move interpolates linearly).
double off_segment(const JointVector& q, const JointVector& a, const JointVector& b) {
  const JointVector d = b - a;
  const double s = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (q - (a + s * d)).norm();
}

}  // namespace

TEST_CASE("interrupt: a joint move halts at a checked pose between start and target and resumes", "[simulator][interrupt]") {
  for (const Stepping stepping : {Stepping::fixed, Stepping::gap}) {
    INFO("stepping " << (stepping == Stepping::fixed ? "fixed" : "gap"));
    const JointVector start = jv({0, -90, 90, 0, 0, 0});
    const JointVector target = jv({60, -45, 150, 20, 40, 30});
    // Reference: the same motion, not interrupted, traced.
    Simulator ref(cell_with(stepping));
    ref.recorders().trace.on = true;
    REQUIRE(ref.start_joint_move(target, {}, 4).status == MotionStatus::ok);
    REQUIRE(ref.finish_motion().status == MotionStatus::ok);
    const auto& poses = ref.recorders().trace.samples;  // the start pose, then every checked pose up to the target
    REQUIRE(poses.size() >= 4);
    const double total_s = ref.time_s();

    Simulator sim(cell_with(stepping));
    sim.recorders().trace.on = true;
    FlagAfter stop;
    stop.n = static_cast<int>(poses.size()) / 2;
    stop.attach(sim);
    REQUIRE(sim.start_joint_move(target, {}, 4).status == MotionStatus::ok);
    const MotionResult r = sim.finish_motion();
    REQUIRE(r.status == MotionStatus::interrupted);
    CHECK_FALSE(sim.motion_pending());
    // Halted exactly at the n-th checked pose of the uninterrupted run, the clock there.
    const TraceSample& at = poses[static_cast<std::size_t>(stop.n - 1)];
    CHECK(sim.recorders().counts.poses == static_cast<std::uint64_t>(stop.n));
    CHECK((sim.joints() - at.joints).norm() == 0);
    CHECK(sim.time_s() == at.time_s);
    CHECK(sim.time_s() > 0);
    CHECK(sim.time_s() < total_s);
    CHECK((sim.joints() - start).norm() > 1);
    CHECK((sim.joints() - target).norm() > 1);
    CHECK(r.interrupt.step == 4);
    CHECK(r.interrupt.time_s == sim.time_s());
    CHECK((r.interrupt.joints - sim.joints()).norm() == 0);
    CHECK(r.interrupt.path_fraction > 0);
    CHECK(r.interrupt.path_fraction < 1);
    CHECK(off_segment(sim.joints(), start, target) < 1e-9);
    REQUIRE(sim.halted_motion().has_value());
    CHECK(sim.halted_motion()->time_s == sim.time_s());

    // The rest: from where it stopped, along the same joint segment, to the same target.
    stop.flag = false;
    const double t_halt = sim.time_s();
    const std::size_t traced = sim.recorders().trace.samples.size();
    REQUIRE(sim.resume_motion().status == MotionStatus::ok);
    CHECK_FALSE(sim.halted_motion().has_value());
    REQUIRE(sim.finish_motion().status == MotionStatus::ok);
    CHECK((sim.joints() - target).norm() == 0);
    CHECK(sim.time_s() > t_halt);
    REQUIRE(sim.recorders().trace.samples.size() > traced);
    double off = 0;
    for (std::size_t i = traced; i < sim.recorders().trace.samples.size(); ++i) off = std::max(off, off_segment(sim.recorders().trace.samples[i].joints, start, target));
    CHECK(off < 1e-9);
  }
}

TEST_CASE("interrupt: a straight line halts on the line and resumes to its target", "[simulator][interrupt]") {
  const JointVector start = jv({0, -60, 150, 0, 70, 0});
  Simulator ref(cell_with(Stepping::fixed));
  REQUIRE(ref.start_joint_move(start, {}, 1).status == MotionStatus::ok);
  REQUIRE(ref.finish_motion().status == MotionStatus::ok);
  const Location from = ref.here();
  const Location target = trans(150, 100, -200, 0, 0, 0) * from;
  ref.recorders().trace.on = true;
  REQUIRE(ref.start_move(target, true, {}, 2).status == MotionStatus::ok);
  REQUIRE(ref.finish_motion().status == MotionStatus::ok);
  const std::size_t line_poses = ref.recorders().trace.samples.size();
  REQUIRE(line_poses >= 4);
  const double line_s = ref.time_s();

  Simulator sim(cell_with(Stepping::fixed));
  REQUIRE(sim.start_joint_move(start, {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const double t0 = sim.time_s();
  const std::uint64_t before = sim.recorders().counts.poses;
  FlagAfter stop;
  stop.seen = static_cast<int>(before);  // count the line's poses only
  stop.n = static_cast<int>(before + line_poses / 3);
  stop.attach(sim);
  REQUIRE(sim.start_move(target, true, {}, 2).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::interrupted);
  CHECK(sim.recorders().counts.poses - before == line_poses / 3);
  const TraceSample& at = ref.recorders().trace.samples[line_poses / 3 - 1];
  CHECK((sim.joints() - at.joints).norm() == 0);
  CHECK(sim.time_s() == at.time_s);
  CHECK(sim.time_s() > t0);
  CHECK(sim.time_s() < line_s);
  // On the segment, strictly inside it.
  const collision::Vec3 a = from.translation(), b = target.translation(), p = sim.here().translation();
  const collision::Vec3 d = (b - a).normalized();
  CHECK(((p - a) - d * d.dot(p - a)).norm() < 1e-6);
  CHECK(d.dot(p - a) > 1);
  CHECK(d.dot(b - p) > 1);
  CHECK(r.interrupt.path_fraction > 0);
  CHECK(r.interrupt.path_fraction < 1);
  CHECK(r.interrupt.path_fraction == Approx(d.dot(p - a) / (b - a).norm()).epsilon(1e-6));

  stop.flag = false;
  REQUIRE(sim.resume_motion().status == MotionStatus::ok);
  CHECK(sim.dest().isApprox(target, 1e-12));
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK((sim.here().translation() - target.translation()).norm() < 1e-6);
  CHECK((sim.here().linear() - target.linear()).norm() < 1e-9);
}

TEST_CASE("interrupt: a flag already set stops the motion at its start and WAIT and OPENI return it", "[simulator][interrupt]") {
  Simulator sim(cell_with(Stepping::gap));
  REQUIRE(sim.start_joint_move(jv({0, -90, 120, 0, 0, 0}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const double t0 = sim.time_s();
  const JointVector q0 = sim.joints();
  std::atomic<bool> flag{true};
  sim.set_interrupt(&flag);

  REQUIRE(sim.start_joint_move(jv({0, -90, 150, 0, 0, 0}), {}, 2).status == MotionStatus::ok);
  MotionResult r = sim.wait(5.0);
  REQUIRE(r.status == MotionStatus::interrupted);
  CHECK(r.interrupt.path_fraction == 0);
  CHECK(sim.time_s() == t0);  // no motion, and WAIT's 5 s not added
  CHECK((sim.joints() - q0).norm() == 0);

  REQUIRE(sim.resume_motion().status == MotionStatus::ok);
  r = sim.hand_immediate(HandState::closed, 0.5);
  REQUIRE(r.status == MotionStatus::interrupted);
  CHECK(sim.hand().state == HandState::open);  // untouched
  CHECK(sim.time_s() == t0);
  REQUIRE(sim.halted_motion().has_value());

  // Without the flag (null or false) the same motion completes.
  sim.set_interrupt(nullptr);
  REQUIRE(sim.resume_motion().status == MotionStatus::ok);
  REQUIRE(sim.hand_immediate(HandState::closed, 0.5).status == MotionStatus::ok);
  CHECK(sim.hand().state == HandState::closed);
  CHECK((sim.joints() - jv({0, -90, 150, 0, 0, 0})).norm() == 0);
  CHECK(sim.time_s() > t0 + 0.5);
}

TEST_CASE("interrupt: with collision checking off the motion halts too and a new motion drops the rest", "[simulator][interrupt]") {
  Simulator sim(cell_with(Stepping::gap, false));
  FlagAfter stop;
  stop.n = 5;
  stop.attach(sim);
  REQUIRE(sim.start_joint_move(jv({30, -90, 150, 0, 0, 0}), {}, 3).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::interrupted);
  CHECK(sim.recorders().counts.poses == 5);
  CHECK(r.interrupt.path_fraction > 0);
  CHECK(r.interrupt.path_fraction < 1);
  REQUIRE(sim.halted_motion().has_value());
  stop.flag = false;
  stop.n = -1;
  REQUIRE(sim.start_joint_move(jv({0, -90, 90, 0, 0, 0}), {}, 4).status == MotionStatus::ok);
  CHECK_FALSE(sim.halted_motion().has_value());
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const MotionResult none = sim.resume_motion();
  CHECK(none.status == MotionStatus::error);
  CHECK(none.error.message == "*No motion to resume*");
}

TEST_CASE("interrupt: the rest keeps what is left of DURATION and takes the monitor speed given", "[simulator][interrupt]") {
  const JointVector target = jv({0, -90, 100, 0, 0, 0});  // J3 10 deg: ~0.36 s at full speed
  Simulator sim(cell_with(Stepping::fixed));
  FlagAfter stop;
  stop.n = 3;
  stop.attach(sim);
  REQUIRE(sim.start_joint_move(target, {100, 100, -1, 3.0}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::interrupted);
  const double t_halt = sim.time_s();
  CHECK(t_halt > 0);
  CHECK(t_halt < 3.0);
  stop.flag = false;
  REQUIRE(sim.resume_motion().status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(3.0));  // the motion still takes its DURATION in all

  // Without DURATION: the rest at monitor speed 10 takes longer than at 100.
  const auto rest_time = [&](std::optional<double> monitor) {
    Simulator s(cell_with(Stepping::fixed));
    FlagAfter f;
    f.n = 3;
    f.attach(s);
    REQUIRE(s.start_joint_move(jv({0, -90, 150, 0, 0, 0}), {}, 1).status == MotionStatus::ok);
    REQUIRE(s.finish_motion().status == MotionStatus::interrupted);
    const double t = s.time_s();
    f.flag = false;
    REQUIRE(s.resume_motion(monitor).status == MotionStatus::ok);
    REQUIRE(s.finish_motion().status == MotionStatus::ok);
    return s.time_s() - t;
  };
  CHECK(rest_time(10.0) > 5 * rest_time(std::nullopt));
}

TEST_CASE("stop condition: the motion halts at the first checked pose it answers true for", "[simulator][interrupt]") {
  const JointVector target = jv({60, -45, 150, 20, 40, 30});
  Simulator sim(cell_with(Stepping::fixed));
  double asked_first = -1, asked_last = -1;
  // True from t = 0.4 s on: the halt is at the first checked pose at or after it.
  sim.set_stop_condition([&](double t, const JointVector&) {
    if (asked_first < 0) asked_first = t;
    asked_last = t;
    return t >= 0.4;
  });
  REQUIRE(sim.start_joint_move(target, {}, 7).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::interrupted);
  CHECK(r.interrupt.by_condition);
  CHECK(r.interrupt.step == 7);
  CHECK(asked_first == 0);
  CHECK(r.interrupt.time_s == asked_last);
  CHECK(r.interrupt.time_s >= 0.4);
  CHECK(r.interrupt.time_s < 0.45);
  CHECK(sim.time_s() == r.interrupt.time_s);
  CHECK(r.interrupt.path_fraction > 0);
  CHECK(r.interrupt.path_fraction < 1);
  // The flag's interrupts are not the condition's; without a condition the motion completes.
  sim.drop_halted_motion();
  sim.set_stop_condition(nullptr);
  REQUIRE(sim.start_joint_move(target, {}, 8).status == MotionStatus::ok);
  CHECK(sim.finish_motion().status == MotionStatus::ok);
  CHECK((sim.joints() - target).norm() < 1e-9);
}
