// Configuration words derived from joint values, kinematics.md §6.
#include "robots/configuration.hpp"

#include "robots/ik_spherical.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace asimov::robots {

namespace {
// Configuration of a J1 _|_ J2 || J3 spherical-wrist chain, from the same geometry as
// kinematics.md §6. forward = axis2 x axis1 (sign chosen so that the zero-pose wrist centre is
// in front); RIGHTY iff V = (wrist - J1 axis) . forward >= 0. ABOVE iff the elbow (a point of
// axis 3) is on the upper side (towards the J1 axis direction) of the line from the shoulder
// (a point of axis 2) to the wrist centre, within the arm plane -- for the PUMA this is exactly
// sigma_s * wrap(theta2 - atan2(pz, V)) >= 0. NOFLIP iff J5 >= 0.
struct ChainGeometry {
  double v = 0;      // V (uncalibrated)
  double side = 0;   // n . (d x (elbow - shoulder))
  double ref = 0;    // n . (d x up)
};

ChainGeometry chain_geometry(const Robot& robot, const SphericalWristModel& m, const std::vector<Pose>& frames) {
  std::array<Vec3, 3> axis, point;
  for (std::size_t k = 0; k < 3; ++k) {
    const Pose pre = frames[k] * robot.chain[k].origin;
    axis[k] = pre.linear() * robot.chain[k].axis;
    point[k] = pre.translation();
  }
  const Vec3 wrist = frames[6] * (m.zero_flange.inverse() * m.wrist);
  const Vec3 d = wrist - point[1];
  ChainGeometry g;
  g.v = (wrist - point[0]).dot(axis[1].cross(axis[0]));
  g.side = axis[1].dot(d.cross(point[2] - point[1]));
  g.ref = axis[1].dot(d.cross(axis[0]));
  return g;
}

Configuration chain_configuration(const Robot& robot, const SphericalWristModel& m, const JointVector& display) {
  std::vector<Pose> frames;
  frames.reserve(7);
  link_frames(robot, JointVector::Zero(6), frames);
  const double fwd = chain_geometry(robot, m, frames).v < 0 ? -1 : 1;
  link_frames(robot, display, frames);
  const ChainGeometry g = chain_geometry(robot, m, frames);
  Configuration c;
  c.righty = fwd * g.v >= 0;
  c.above = g.side * g.ref >= 0;
  c.noflip = display[4] >= 0;
  return c;
}
}  // namespace

Configuration configuration_of(const Robot& robot, const JointVector& display) {
  if (!is_puma_type(robot)) {
    SphericalWristModel m;
    if (display.size() == 6 && spherical_wrist_model(robot, m)) return chain_configuration(robot, m, display);
    return Configuration{};  // words are defined for PUMA-type and spherical-wrist arms only
  }
  const JointVector q = display_to_dh(robot, display);
  std::vector<Pose> frames;
  frames.reserve(robot.dh.size() + 1);
  link_frames(robot, display, frames);
  const Vec3 p = frames[4].translation();  // wrist centre
  const double V = p.x() * std::cos(q[0]) + p.y() * std::sin(q[0]);
  Configuration c;
  c.righty = V >= 0;
  const double sigma_s = c.righty ? 1 : -1;
  const double diff = std::remainder(q[1] - std::atan2(p.z(), V), 2 * std::numbers::pi);
  c.above = sigma_s * diff >= 0;
  c.noflip = display[4] >= 0;
  return c;
}

Configuration requested_configuration(const Configuration& current, const ConfigurationRequest& r) {
  Configuration c = current;
  if (r.righty >= 0) c.righty = r.righty == 1;
  if (r.above >= 0) c.above = r.above == 1;
  if (r.noflip >= 0) c.noflip = r.noflip == 1;
  return c;
}

}  // namespace asimov::robots
