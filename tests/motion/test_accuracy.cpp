// The run's own accuracy figures (Simulator::accuracy): the §6.3 step bound against real vertex
// displacements, FK(IK(target)) residuals, straight-line deviation between checked poses, the
// contact bracket; and gap stepping (docs/collision-method.md §6.3) against fixed stepping on random motions.
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"
#include "support/geometry.hpp"
#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {

// The default cell of app/: PUMA, gripper-sized tool, table and box.
Cell puma_cell(double step_mm = 1.0, Stepping stepping = Stepping::fixed) {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = jv({0, -90, 90, 0, 0, 0});
  c.tool = trans(0, 0, 200, 0, 0, 0);
  c.tool_shape = collision::transformed(collision::make_box({50, 80, 140}), collision::Pose(Eigen::Translation3d(0, 0, 130)));
  c.objects.push_back(test::box_object("table", {700, 1200, 40}, {750, 0, -420}));
  c.objects.push_back(test::box_object("box", {160, 160, 200}, {600, 250, -300}));
  c.collision.step_mm = step_mm;
  c.collision.stepping = stepping;
  return c;
}

// World vertices of every moving body (links k > 0, then the tool) at display joints q.
std::vector<collision::Vec3> moving_vertices(const Cell& cell, const JointVector& q) {
  std::vector<collision::Pose> f;
  robots::link_frames(cell.robot, q, f);
  std::vector<collision::Vec3> out;
  for (const auto& b : cell.robot.bodies)
    if (b.link > 0)
      for (const auto& v : b.mesh.vertices) out.push_back(cell.base * f[static_cast<std::size_t>(b.link)] * v);
  for (const auto& v : cell.tool_shape->vertices) out.push_back(cell.base * f.back() * v);
  return out;
}

// A joint move, a straight line with a turn of the tool, a MOVE to a location.
void run_mixed(Simulator& sim) {
  REQUIRE(sim.start_joint_move(jv({20, -70, 160, 10, 40, 20}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const Location line_to = trans(-60, 80, -120, 0, 0, 0) * sim.here() * trans(0, 0, 0, 0, 25, 0);
  const MotionResult r = sim.start_move(line_to, true, {}, 2);
  INFO(r.error.message << " " << r.error.detail);
  REQUIRE(r.status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  REQUIRE(sim.start_move(trans(100, -100, 50, 0, 0, 0) * sim.here(), false, {}, 3).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
}

}  // namespace

TEST_CASE("accuracy: the step displacement bound covers every real vertex displacement", "[simulator][accuracy]") {
  for (const Stepping stepping : {Stepping::fixed, Stepping::gap}) {
    const Cell cell = puma_cell(1.0, stepping);
    Simulator sim(cell);
    sim.recorders().trace.on = true;
    run_mixed(sim);
    const auto& tr = sim.recorders().trace.samples;
    REQUIRE(tr.size() > 3);
    double real = 0;  // largest displacement of a body vertex between consecutive checked poses
    std::vector<collision::Vec3> prev = moving_vertices(cell, tr.front().joints);
    for (std::size_t i = 1; i < tr.size(); ++i) {
      const auto now = moving_vertices(cell, tr[i].joints);
      for (std::size_t v = 0; v < now.size(); ++v) real = std::max(real, (now[v] - prev[v]).norm());
      prev = now;
    }
    const double bound = sim.recorders().accuracy.figures.step_displacement_mm;
    INFO("stepping " << (stepping == Stepping::gap ? "gap" : "fixed") << ": real " << real << " mm, bound " << bound);
    CHECK(real <= bound);
    CHECK(real > 0.1 * bound);  // the bound is an upper bound, not a vacuous one
    if (stepping == Stepping::fixed) CHECK(bound <= 1.0);
    CHECK(sim.recorders().accuracy.figures.motions == 3);
  }
}

TEST_CASE("accuracy: IK residuals of the PUMA are at rounding level", "[simulator][accuracy]") {
  Simulator sim(puma_cell());
  run_mixed(sim);
  const RunAccuracy& a = sim.recorders().accuracy.figures;
  CHECK(a.ik_solves > 100);  // the line's samples and the MOVE target
  CHECK(a.ik_residual.position_mm <= 1e-9);
  CHECK(a.ik_residual.rotation_rad <= 1e-12);
}

TEST_CASE("accuracy: straight-line deviation between checked poses shrinks with step_mm", "[simulator][accuracy]") {
  double previous = std::numeric_limits<double>::infinity();
  for (const double step : {4.0, 1.0, 0.25}) {
    Cell cell = puma_cell(step);
    cell.objects.clear();
    cell.start_joints = jv({20, -70, 160, 10, 40, 20});
    Simulator sim(cell);
    const Location to = trans(-150, 200, -100, 0, 0, 0) * sim.here() * trans(0, 0, 0, 30, 40, 0);
    REQUIRE(sim.start_move(to, true, {}, 1).status == MotionStatus::ok);
    REQUIRE(sim.finish_motion().status == MotionStatus::ok);
    const RunAccuracy& a = sim.recorders().accuracy.figures;
    INFO("step " << step << ": " << a.line_deviation.position_mm << " mm, " << a.line_deviation.rotation_rad << " rad, "
                 << a.line_intervals << " intervals");
    CHECK(a.line_intervals == sim.recorders().counts.poses - 1);  // every checked pose but the start one
    CHECK(a.line_deviation.position_mm > 0);
    CHECK(a.line_deviation.position_mm < previous);
    CHECK(a.line_deviation.position_mm < 0.1);
    previous = a.line_deviation.position_mm;
  }
}

TEST_CASE("accuracy: the contact bracket is within toc_tolerance_s", "[simulator][accuracy][toc]") {
  for (const double tol : {1e-3, 1e-6}) {
    Cell cell = puma_cell();
    cell.collision.toc_tolerance_s = tol;
    cell.start_joints = jv({-40, -20, 169, 90, -90, 0});  // the crash demo's sweep into the box
    Simulator sim(cell);
    CHECK_FALSE(sim.recorders().accuracy.figures.contacts);
    REQUIRE(sim.start_joint_move(jv({60, -20, 169, 90, -90, 0}), {50, 50, -1, 0}, 1).status == MotionStatus::ok);
    const MotionResult r = sim.finish_motion();
    REQUIRE(r.status == MotionStatus::collision);
    const RunAccuracy& a = sim.recorders().accuracy.figures;
    CHECK(a.contacts == 1);
    CHECK(a.contact_bracket_s == r.collision.time_s - r.collision.time_free_s);
    CHECK(a.contact_bracket_s <= tol);
    CHECK(a.contact_bracket_s > 0);
  }
}

TEST_CASE("timing: every phase of a run is measured, the caller adds the parse time", "[simulator][accuracy]") {
  Simulator sim(puma_cell());
  const RunTiming& t = sim.recorders().timing.timing;
  CHECK(t.preprocess_s > 0);  // the engine was built in the constructor
  run_mixed(sim);
  CHECK(t.motion_s > 0);
  CHECK(t.collision_s > 0);
  CHECK(t.parse_s == 0);
  sim.recorders().timing.timing.parse_s += 0.5;
  CHECK(t.parse_s == 0.5);
}

TEST_CASE("gap stepping: the same first contact as fixed stepping on random motions, fewer poses", "[simulator][gap]") {
  const double clearance = GENERATE(0.0, 4.0);
  std::mt19937 rng(20261128);
  std::uniform_real_distribution<double> u(-1, 1);
  int contacts = 0, free = 0;
  std::uint64_t poses_fixed = 0, poses_gap = 0;
  // Random joint moves and straight lines near the table and the box from random free starts.
  for (int trial = 0; trial < 60; ++trial) {
    const JointVector start = jv({u(rng) * 60, -40 + u(rng) * 30, 170 + u(rng) * 20, u(rng) * 90, -60 + u(rng) * 40, u(rng) * 90});
    const bool straight = trial % 3 == 2;
    const JointVector target = start + jv({u(rng) * 60, u(rng) * 25, u(rng) * 25, u(rng) * 60, u(rng) * 40, u(rng) * 60});
    const Location line_to = trans(u(rng) * 200, u(rng) * 200, -150 + u(rng) * 100, 0, 0, 0);
    struct Outcome {
      MotionResult start, end;
      std::uint64_t poses = 0;
    } out[2];
    for (const Stepping st : {Stepping::fixed, Stepping::gap}) {
      Cell cell = puma_cell(1.0, st);
      cell.start_joints = start;
      cell.collision.clearance_mm = clearance;
      Simulator sim(cell);
      Outcome& o = out[st == Stepping::gap];
      o.start = straight ? sim.start_move(line_to * sim.here(), true, {}, 1) : sim.start_joint_move(target, {}, 1);
      if (o.start.status == MotionStatus::ok) o.end = sim.finish_motion();
      o.poses = sim.recorders().counts.poses;
    }
    INFO("clearance " << clearance << ", trial " << trial << (straight ? " (line)" : " (joint move)"));
    REQUIRE(out[0].start.status == out[1].start.status);
    if (out[0].start.status != MotionStatus::ok) continue;
    REQUIRE(out[0].end.status == out[1].end.status);
    CHECK(out[1].poses <= out[0].poses);
    poses_fixed += out[0].poses, poses_gap += out[1].poses;
    if (out[0].end.status != MotionStatus::collision) {
      ++free;
      continue;
    }
    ++contacts;
    const CollisionReport &f = out[0].end.collision, &g = out[1].end.collision;
    CHECK(f.body_a == g.body_a);
    CHECK(f.body_b == g.body_b);
    CHECK(std::abs(f.time_s - g.time_s) <= 1e-6);
  }
  WARN("gap vs fixed stepping, clearance " << clearance << " mm: " << contacts << " contacts, " << free << " free motions, poses " << poses_gap << " vs "
                                 << poses_fixed);
  CHECK(contacts >= 5);
  CHECK(free >= 5);
  CHECK(poses_gap * 3 < poses_fixed);
}

TEST_CASE("gap stepping: pair bounds and grid intervals", "[sampler][gap]") {
  const robots::Robot robot = robots::puma560();
  std::vector<robots::BodyReach> reach;
  for (const auto& b : robot.bodies) reach.push_back(robots::body_reach(robot, b.mesh, b.link));
  int l2 = -1, l4 = -1;
  for (std::size_t i = 0; i < robot.bodies.size(); ++i) {
    if (robot.bodies[i].link == 2) l2 = static_cast<int>(i);
    if (robot.bodies[i].link == 4) l4 = static_cast<int>(i);
  }
  REQUIRE(l2 >= 0);
  REQUIRE(l4 >= 0);
  const GapPair self{l2, l4, 2, 4, 10};
  const GapPair fixed_body{-1, l4, 0, 4, 10};
  // J1 and J2 turn both links alike: their distance cannot change, the object's can.
  const JointVector shoulder = jv({3, 2, 0, 0, 0, 0});
  CHECK(pair_displacement(reach, self, shoulder) == 0);
  CHECK(pair_displacement(reach, fixed_body, shoulder) == robots::max_displacement(reach[l4], shoulder));
  // J3 moves link 4 against link 2: bounded by, and here below, the sum of both bounds.
  const JointVector elbow = jv({3, 2, 1, 0, 0, 0});
  const double d = pair_displacement(reach, self, elbow);
  CHECK(d > 0);
  CHECK(d < robots::max_displacement(reach[l2], elbow) + robots::max_displacement(reach[l4], elbow));
  // Allowance: max(c, step, g - c).
  CHECK(gap_allowance(0.2, 0, 1) == 1);
  CHECK(gap_allowance(50, 2, 1) == 48);
  CHECK(gap_allowance(3, 2.5, 1) == 2.5);
  // Intervals: the most every pair allows, at least one, at most what is left.
  const std::vector<GapPair> pairs{{0, 1, 1, 2, 10}, {-1, 1, 0, 2, 3}};
  CHECK(gap_intervals(std::vector<double>{1, 1}, pairs, 100) == 3);
  CHECK(gap_intervals(std::vector<double>{1, 0}, pairs, 100) == 10);
  CHECK(gap_intervals(std::vector<double>{0, 0}, pairs, 100) == 100);
  CHECK(gap_intervals(std::vector<double>{5, 5}, pairs, 100) == 1);
  CHECK(gap_intervals(std::vector<double>{1, 1}, pairs, 2) == 2);
}
