// Analytic contact scenes for the work-precision reports (docs/accuracy.md): cells built in code
// whose first contact instant and point follow in closed form from the geometry and the motion
// profile. Shared by bench/bench_accuracy.cpp and tests/motion/test_accuracy_scenes.cpp (which
// checks these answers against the simulator at a coarse setting).
//
// 1. box_onto_plane: a tilted tool box lowered by a straight line onto a plate; its lowest
//    corner touches the plate's top at sigma* = (z_corner - z_top) / L.
// 2. j1_into_wall: the PUMA swings about J1 into a wall plane y = Y0; the first arm vertex to
//    reach the plane does so at theta = asin(Y0 / r) - phi.
// 3. edge_on_edge: a tool rod with a horizontal lowest edge along x, lowered onto a ridge whose
//    top edge runs along y; the edges meet at their crossing point.
// The instant is t* = profile.time_at(sigma*) of the motion's trapezoid. For the straight lines
// the translation axis must set the profile (checked by straight_line_duration_matches()).
#pragma once
#include "asimov/motion/cell.hpp"
#include "asimov/motion/profile.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace asimov::accuracy {

using collision::Vec3;
using motion::Cell;
using motion::Location;
using robots::JointVector;

struct AnalyticScene {
  std::string name;
  Cell cell;
  bool straight = false;
  Location target = Location::Identity();  // straight: world target of the tool point
  JointVector target_joints;               // joint move: display target
  double drop_mm = 0;                      // straight: length of the (vertical) line
  double t_star = 0;                       // analytic first-contact instant [s]
  Vec3 point_star = Vec3::Zero();          // analytic first-contact point, world [mm]
  std::string static_body;                 // the object that is hit
  std::string moving_body;                 // the arm body that hits it ("tool", "link3", ...)
};

inline JointVector joints(std::initializer_list<double> v) {
  JointVector q(static_cast<int>(v.size()));
  int i = 0;
  for (double x : v) q[i++] = x;
  return q;
}

inline motion::CellObject box_object(const std::string& name, const Vec3& size, const Location& pose) {
  motion::CellObject o;
  o.name = name;
  o.mesh = collision::make_box(size);
  o.pose = pose;
  return o;
}

inline Location at(const Vec3& p, const Eigen::Matrix3d& r = Eigen::Matrix3d::Identity()) {
  Location l = Location::Identity();
  l.linear() = r;
  l.translation() = p;
  return l;
}

inline Eigen::Matrix3d rot(double deg, const Vec3& axis) {
  return Eigen::AngleAxisd(deg * std::numbers::pi / 180, axis.normalized()).toRotationMatrix();
}

// Start joints of the straight-line scenes: the flange z axis points straight down.
inline JointVector down_joints() { return joints({0, -50, 190, 0, 40, 0}); }

// The tool's world vertices at display joints q.
inline std::vector<Vec3> tool_vertices(const Cell& cell, const JointVector& q) {
  const collision::Pose f = cell.base * robots::flange_pose(cell.robot, q);
  std::vector<Vec3> out;
  for (const auto& v : cell.tool_shape->vertices) out.push_back(f * v);
  return out;
}

// Trapezoid of a pure straight-line translation of length L at full speed.
inline motion::Profile translation_profile(const robots::Robot& r, double length_mm) {
  const motion::ProfileAxis axis{length_mm, r.max_tool_speed, r.max_tool_accel};
  return motion::plan_profile(std::span(&axis, 1));
}

// Common part of the straight-line scenes: PUMA at down_joints(), tool = `box` placed at
// `world_pose` (converted into the flange frame), lowered by `drop_mm`.
inline AnalyticScene lowered_tool(const std::string& name, const Vec3& box, const Location& world_pose, double drop_mm) {
  AnalyticScene s;
  s.name = name;
  s.cell.robot = robots::puma560();
  s.cell.start_joints = down_joints();
  const Location flange = robots::flange_pose(s.cell.robot, s.cell.start_joints);
  s.cell.tool_shape = collision::transformed(collision::make_box(box), flange.inverse() * world_pose);
  s.straight = true;
  s.drop_mm = drop_mm;
  s.target = motion::trans(0, 0, -drop_mm, 0, 0, 0) * flange;  // TOOL = identity: tool point = flange
  s.moving_body = "tool";
  return s;
}

// 1. A 40 x 30 x 20 mm box, turned 20 deg about x and 30 deg about y so that one corner is
// lowest, 100 mm below the flange; the plate's top 60 mm below that corner; drop 150 mm.
inline AnalyticScene box_onto_plane() {
  const robots::Robot puma = robots::puma560();
  const Location flange = robots::flange_pose(puma, down_joints());
  const Vec3 c = flange.translation() + Vec3(0, 0, -100);
  constexpr double kDrop = 150, kGap = 60.3;  // not on a 1 mm or step_mm sample: a sample exactly at
                                              // contact would make plain stepping exact
  AnalyticScene s = lowered_tool("box_onto_plane", {40, 30, 20}, at(c, rot(30, Vec3::UnitY()) * rot(20, Vec3::UnitX())), kDrop);
  const auto verts = tool_vertices(s.cell, s.cell.start_joints);
  Vec3 low = verts.front();
  int at_min = 0;
  for (const auto& v : verts) low = v.z() < low.z() ? v : low;
  for (const auto& v : verts) at_min += v.z() < low.z() + 1e-6;
  if (at_min != 1) throw std::logic_error("box_onto_plane: the lowest corner is not unique");
  const double top = low.z() - kGap;
  s.cell.objects.push_back(box_object("plate", {200, 200, 10}, at({c.x(), c.y(), top - 5})));
  s.static_body = "plate";
  s.t_star = translation_profile(puma, kDrop).time_at(kGap / kDrop);
  s.point_star = {low.x(), low.y(), top};
  return s;
}

// 3. A 120 x 30 x 30 mm rod (long along world x) turned 45 deg about x: its lowest edge runs
// along x at y = c.y. The ridge, 30 x 200 x 30 mm turned 45 deg about y, has its top edge along
// y at x = c.x + 20, 50 mm below the rod's edge. Drop 120 mm.
inline AnalyticScene edge_on_edge() {
  const robots::Robot puma = robots::puma560();
  const Location flange = robots::flange_pose(puma, down_joints());
  const Vec3 c = flange.translation() + Vec3(0, 0, -100);
  constexpr double kDrop = 120, kGap = 50, kHalfDiag = 15 * std::numbers::sqrt2;
  AnalyticScene s = lowered_tool("edge_on_edge", {120, 30, 30}, at(c, rot(45, Vec3::UnitX())), kDrop);
  const double edge_z = c.z() - kHalfDiag;
  const double ridge_top = edge_z - kGap;
  const Vec3 ridge_c(c.x() + 20, c.y(), ridge_top - kHalfDiag);
  s.cell.objects.push_back(box_object("ridge", {30, 200, 30}, at(ridge_c, rot(45, Vec3::UnitY()))));
  s.static_body = "ridge";
  s.t_star = translation_profile(puma, kDrop).time_at(kGap / kDrop);
  s.point_star = {ridge_c.x(), c.y(), ridge_top};
  return s;
}

// 2. The PUMA, forearm horizontal along +x, turns J1 from 0 to 60 deg into the wall y >= 200
// (x in [-200, 1000], z in [0, 800]). J1 alone moves: one profile axis, sigma = theta / 60 deg.
inline AnalyticScene j1_into_wall() {
  AnalyticScene s;
  s.name = "j1_into_wall";
  s.cell.robot = robots::puma560();
  s.cell.start_joints = joints({0, -90, 180, 0, 0, 0});
  constexpr double kY0 = 200, kSweepDeg = 60;
  s.cell.objects.push_back(box_object("wall", {1200, 50, 800}, at({400, kY0 + 25, 400})));
  s.static_body = "wall";
  s.target_joints = joints({kSweepDeg, -90, 180, 0, 0, 0});
  std::vector<collision::Pose> f;
  robots::link_frames(s.cell.robot, s.cell.start_joints, f);
  double theta = std::numeric_limits<double>::infinity();
  Vec3 first = Vec3::Zero();
  for (const auto& b : s.cell.robot.bodies) {
    if (b.link == 0) continue;
    for (const auto& v0 : b.mesh.vertices) {
      const Vec3 v = s.cell.base * f[static_cast<std::size_t>(b.link)] * v0;
      if (v.y() >= kY0) throw std::logic_error("j1_into_wall: the arm starts in the wall");
      const double r = std::hypot(v.x(), v.y());
      if (r <= kY0) continue;
      double th = std::asin(kY0 / r) - std::atan2(v.y(), v.x());
      if (th < 0) th += 2 * std::numbers::pi;
      if (th < theta) theta = th, first = v, s.moving_body = b.name;
    }
  }
  const Vec3 touch = Eigen::AngleAxisd(theta, Vec3::UnitZ()) * first;
  if (!(touch.x() > -200 && touch.x() < 1000 && touch.z() > 0 && touch.z() < 800))
    throw std::logic_error("j1_into_wall: the first vertex meets the wall plane outside the wall");
  const double theta_deg = theta * 180 / std::numbers::pi;
  const motion::ProfileAxis axis{kSweepDeg, s.cell.robot.max_velocity[0], s.cell.robot.max_acceleration[0]};
  s.t_star = motion::plan_profile(std::span(&axis, 1)).time_at(theta_deg / kSweepDeg);
  s.point_star = touch;
  return s;
}

inline std::vector<AnalyticScene> analytic_scenes() { return {box_onto_plane(), j1_into_wall(), edge_on_edge()}; }

inline motion::MotionResult start(motion::Simulator& sim, const AnalyticScene& s, int step = 1) {
  return s.straight ? sim.start_move(s.target, true, {}, step) : sim.start_joint_move(s.target_joints, {}, step);
}

// One motion of the scene with `settings`; the result of finish_motion().
inline motion::MotionResult run(const AnalyticScene& s, const motion::CollisionSettings& settings) {
  Cell cell = s.cell;
  cell.collision = settings;
  motion::Simulator sim(std::move(cell));
  if (const auto r = start(sim, s); r.status != motion::MotionStatus::ok) return r;
  return sim.finish_motion();
}

// For a straight-line scene: the motion without collision checks lasts exactly the duration of
// translation_profile(), i.e. the translation axis sets the trapezoid and t* applies.
inline bool straight_line_duration_matches(const AnalyticScene& s, double step_mm) {
  Cell cell = s.cell;
  cell.collision.enabled = false;
  cell.collision.step_mm = step_mm;
  motion::Simulator sim(std::move(cell));
  if (start(sim, s).status != motion::MotionStatus::ok || sim.finish_motion().status != motion::MotionStatus::ok)
    return false;
  return std::abs(sim.time_s() - translation_profile(s.cell.robot, s.drop_mm).duration) < 1e-12;
}

}  // namespace asimov::accuracy
