// Contact time by bisection (docs/collision-method.md §6.4): a J1 sweep of the PUMA into a wall, whose
// contact time follows analytically from the vertices and the profile, and a straight line
// lowering a tool onto a plate, whose contact depth follows from the line.
#include "asimov/motion/profile.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"
#include "support/geometry.hpp"
#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {

// World vertices of every moving body (links k > 0, then the tool) at display joints q.
std::vector<collision::Vec3> moving_vertices(const Cell& cell, const JointVector& q, bool tool_only = false) {
  std::vector<collision::Pose> f;
  robots::link_frames(cell.robot, q, f);
  std::vector<collision::Vec3> out;
  if (!tool_only)
    for (const auto& b : cell.robot.bodies)
      if (b.link > 0)
        for (const auto& v : b.mesh.vertices) out.push_back(cell.base * f[static_cast<std::size_t>(b.link)] * v);
  if (cell.tool_shape)
    for (const auto& v : cell.tool_shape->vertices) out.push_back(cell.base * f.back() * v);
  return out;
}

}  // namespace

TEST_CASE("contact time: a J1 sweep into a wall is bisected to the analytic time", "[simulator][collision][toc]") {
  Cell cell;
  cell.robot = robots::puma560();
  const JointVector start = jv({0, -90, 180, 0, 0, 0});  // forearm horizontal along +x
  cell.start_joints = start;
  // The wall fills y >= Y0 over x in [-200, 1000], z in [0, 800].
  constexpr double Y0 = 200;
  cell.objects.push_back(test::box_object("wall", {1200, 50, 800}, {400, Y0 + 25, 400}));

  // J1 turns every point about the world z axis: a vertex at radius r and angle phi first
  // reaches the plane y = Y0 at theta = asin(Y0 / r) - phi. The first contact of the arm with
  // the half-space is at a vertex, and it lies inside the wall's face (checked below).
  const auto verts = moving_vertices(cell, start);
  double theta = std::numeric_limits<double>::infinity();
  collision::Vec3 first = collision::Vec3::Zero();
  for (const auto& v : verts) {
    REQUIRE(v.y() < Y0);  // free at the start
    const double r = std::hypot(v.x(), v.y());
    if (r <= Y0) continue;
    double th = std::asin(Y0 / r) - std::atan2(v.y(), v.x());
    if (th < 0) th += 2 * std::numbers::pi;
    if (th < theta) theta = th, first = v;
  }
  REQUIRE(theta < std::numbers::pi / 3);
  const Eigen::AngleAxisd turn(theta, collision::Vec3::UnitZ());
  const collision::Vec3 touch = turn * first;
  CHECK(touch.y() == Approx(Y0));
  REQUIRE(touch.x() > -200);
  REQUIRE(touch.x() < 1000);
  REQUIRE(touch.z() > 0);
  REQUIRE(touch.z() < 800);

  // J1 from 0 to 60 deg alone: one profile axis; sigma = theta / 60 deg.
  const double theta_deg = theta * 180 / std::numbers::pi;
  const ProfileAxis axis{60, cell.robot.max_velocity[0], cell.robot.max_acceleration[0]};
  const Profile profile = plan_profile(std::span(&axis, 1));
  const double t_star = profile.time_at(theta_deg / 60);

  Simulator sim(cell);
  REQUIRE(sim.start_joint_move(jv({60, -90, 180, 0, 0, 0}), {}, 3).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::collision);
  const CollisionReport& c = r.collision;
  CHECK((c.body_a == "wall" || c.body_b == "wall"));
  const double tol = cell.collision.toc_tolerance_s;
  CHECK(c.time_s - c.time_free_s <= tol);
  CHECK(c.time_free_s < c.time_s);
  // The bracket holds the analytic time (the inversion and vertex rounding are far below 1e-9 s).
  CHECK(c.time_free_s <= t_star + 1e-9);
  CHECK(c.time_s >= t_star - 1e-9);
  CHECK(std::abs(c.time_s - t_star) <= tol + 1e-9);
  CHECK(c.joints[0] == Approx(theta_deg).margin(1e-6));
  CHECK((c.point - touch).norm() < 1e-3);  // the touching vertex, within the motion of 1e-6 s
  // The arm halts at the free pose, the clock at the contact.
  CHECK(sim.time_s() == c.time_s);
  CHECK(sim.joints()[0] <= c.joints[0]);
  CHECK(c.joints[0] - sim.joints()[0] < 1e-4);
  for (const auto& v : moving_vertices(cell, sim.joints())) CHECK(v.y() < Y0);
  // log2(sample spacing / 1e-6 s) midpoints and one check of the halting pose against every pair.
  CHECK(sim.recorders().counts.bisection >= 5);
  CHECK(sim.recorders().counts.bisection <= 30);
  WARN("J1 sweep: t* = " << t_star << " s, reported " << c.time_s << " s (error " << c.time_s - t_star
                         << " s), bracket " << c.time_s - c.time_free_s << " s, " << sim.recorders().counts.bisection
                         << " bisection checks, " << sim.recorders().counts.poses << " sampled poses");
}

TEST_CASE("contact time: a straight line lowers a tool onto a plate", "[simulator][collision][toc]") {
  Cell cell;
  cell.robot = robots::puma560();
  cell.start_joints = jv({0, -50, 190, 0, 40, 0});  // the flange z axis points down
  // A rod along the flange z axis, 40 to 160 mm out: the lowest part of the arm.
  cell.tool_shape = collision::transformed(collision::make_box({20, 20, 120}), collision::Pose(Eigen::Translation3d(0, 0, 100)));
  Simulator probe(cell);
  const Location start = probe.here();
  double low = std::numeric_limits<double>::infinity();
  for (const auto& v : moving_vertices(cell, cell.start_joints, true)) low = std::min(low, v.z());
  REQUIRE(low < start.translation().z() - 100);  // the rod hangs below the flange
  const double top = low - 60;                      // the plate's top face, 60 mm below the rod
  // A 200 mm square plate under the rod: only the rod is above it.
  cell.objects.push_back(test::box_object("plate", {200, 200, 10}, {start.translation().x(), start.translation().y(), top - 5}));

  Simulator sim(cell);
  REQUIRE(sim.start_move(trans(0, 0, -150, 0, 0, 0) * start, true, {}, 9).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::collision);
  const CollisionReport& c = r.collision;
  CHECK(((c.body_a == "tool" && c.body_b == "plate") || (c.body_a == "plate" && c.body_b == "tool")));
  CHECK(c.time_s - c.time_free_s <= cell.collision.toc_tolerance_s);
  // The line translates the tool: at t_hit its lowest vertex is on the plate (within the
  // 1e-6 s bracket at <= 500 mm/s, and the IK), at the halting pose just above it.
  double low_hit = std::numeric_limits<double>::infinity(), low_free = low_hit;
  for (const auto& v : moving_vertices(cell, c.joints, true)) low_hit = std::min(low_hit, v.z());
  for (const auto& v : moving_vertices(cell, sim.joints(), true)) low_free = std::min(low_free, v.z());
  CHECK(low_hit <= top + 1e-9);
  CHECK(low_hit > top - 1e-3);
  CHECK(low_free > top);
  CHECK(low_free < top + 1e-3);
  CHECK(std::abs(c.point.z() - top) < 1e-3);
  for (const auto& name : {std::string("tool"), std::string("plate")}) {
    const auto [mesh, pose] = test::body_in_world(cell, name, c.joints);
    CHECK(test::point_surface_distance(c.point, mesh, pose) < 0.01);
  }
  WARN("straight line: tool " << top - low_hit << " mm into the plate at t_hit, " << low_free - top
                              << " mm above at t_free, " << sim.recorders().counts.bisection << " bisection checks");
}
