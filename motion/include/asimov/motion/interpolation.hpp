// Path interpolation: joint-space lines and Cartesian straight lines (position linear,
// orientation by quaternion slerp, docs/kinematics.md §8). sigma in [0, 1] comes from the profile.
#pragma once
#include "asimov/motion/location.hpp"
#include "asimov/robots/robot.hpp"
#include <Eigen/Geometry>

namespace asimov::motion {

robots::JointVector interpolate_joints(const robots::JointVector& from, const robots::JointVector& to, double s);

struct LinePath {
  Location from = Location::Identity(), to = Location::Identity();
  Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity(), q1 = Eigen::Quaterniond::Identity();
  double omega = 0;   // half the rotation angle [rad] (q1 already on the shortest arc)
  double length = 0;  // translation distance [mm]
  double angle_deg() const;  // rotation distance 2*omega [deg]
};

LinePath make_line(const Location& from, const Location& to);
Location line_pose(const LinePath& path, double s);

}  // namespace asimov::motion
