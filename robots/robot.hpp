// A serial arm: standard DH chain, display-angle mapping, limits, link bodies.
// Joint values crossing this interface are DISPLAY values (VAL convention, degrees; mm for
// prismatic joints); the DH angles are internal and converted in exactly one place.
#pragma once
#include "collision/polyhedron.hpp"
#include <Eigen/Core>
#include <string>
#include <vector>

namespace asimov::robots {

using collision::Pose;
using collision::Vec3;

constexpr int kMaxJoints = 8;
// Fixed capacity, no heap: joint vectors live in the per-pose hot path.
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxJoints, 1>;

struct DhLink {
  double d = 0, a = 0, alpha = 0;  // [mm], [mm], [rad]; A = Rz(theta) Tz(d) Tx(a) Rx(alpha)
};

// theta_dh [rad] = sign * display [deg] * pi/180 + offset [rad]
struct JointMapping {
  double sign = 1;
  double offset = 0;
};

struct LinkBody {
  int link = 0;                  // 0 = base column (fixed), k = moves with DH frame k
  std::string name;              // "link0" ... "link6"
  collision::Polyhedron mesh;    // in DH frame `link`
};

struct Robot {
  std::string name;
  std::vector<DhLink> dh;
  std::vector<JointMapping> mapping;
  JointVector lower, upper;      // display limits [deg]
  JointVector max_velocity;      // [deg/s] at SPEED 100
  JointVector max_acceleration;  // [deg/s^2]
  double max_tool_speed = 500;   // straight-line translation [mm/s]
  double max_tool_accel = 2000;  // [mm/s^2]
  double max_tool_rot_speed = 90;   // straight-line rotation [deg/s]
  double max_tool_rot_accel = 360;  // [deg/s^2]
  std::vector<LinkBody> bodies;
  int joint_count() const { return static_cast<int>(dh.size()); }
};

// Converts display joint values [deg] to DH angles [rad] and back (the only place that does).
JointVector display_to_dh(const Robot& robot, const JointVector& display);
JointVector dh_to_display(const Robot& robot, const JointVector& dh);

// frames[0] = robot base (identity), frames[k] = DH frame k, k = 1..n; flange = frames[n].
void link_frames(const Robot& robot, const JointVector& display, std::vector<Pose>& frames);
Pose flange_pose(const Robot& robot, const JointVector& display);

// Index of the first joint outside its limits, or -1.
int first_limit_violation(const Robot& robot, const JointVector& display);

// One standard DH link transform A = Rz(theta) Tz(d) Tx(a) Rx(alpha), theta in radians.
Pose dh_transform(const DhLink& link, double theta);
// Flange pose from DH angles [rad] (no display mapping; used by IK checks).
Pose flange_pose_dh(const Robot& robot, const JointVector& dh);

// Angle helpers [deg]: wrap into (-180, 180].
double wrap_deg(double deg);

}  // namespace asimov::robots
