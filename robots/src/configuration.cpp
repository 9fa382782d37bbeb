// Configuration words derived from joint values, docs/kinematics.md §6.
#include "asimov/robots/configuration.hpp"

#include "asimov/robots/ik_scara.hpp"
#include "asimov/robots/ik_spherical.hpp"
#include "asimov/robots/ik_viper.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace asimov::robots {


Configuration configuration_of(const Robot& robot, const JointVector& display) {
  if (is_viper_type(robot)) return viper_configuration(robot, display);
  if (ScaraModel sm; scara_model(robot, sm)) return scara_configuration(robot, sm, display);
  if (!is_puma_type(robot)) {
    SphericalWristModel m;
    if (display.size() == 6 && spherical_wrist_model(robot, m)) return spherical_configuration(robot, m, display);
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

bool configuration_word_applies(const Robot& robot, ConfigurationWord word) {
  if (is_puma_type(robot) || is_viper_type(robot)) return true;
  if (ScaraModel sm; scara_model(robot, sm)) return word == ConfigurationWord::arm;
  SphericalWristModel m;
  return spherical_wrist_model(robot, m);
}

Configuration requested_configuration(const Configuration& current, const ConfigurationRequest& r) {
  Configuration c = current;
  if (r.righty >= 0) c.righty = r.righty == 1;
  if (r.above >= 0) c.above = r.above == 1;
  if (r.noflip >= 0) c.noflip = r.noflip == 1;
  return c;
}

}  // namespace asimov::robots
