// Configuration words derived from joint values, docs/kinematics.md §6.
#include "asimov/robots/configuration.hpp"

#include "ik_family.hpp"

#include "asimov/robots/ik_spherical.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace asimov::robots {


Configuration configuration_of(const Robot& robot, const JointVector& display) {
  if (const IkFamily* f = ik_family_of(robot)) return f->configuration(robot, display);
  SphericalWristModel m;
  if (display.size() == 6 && spherical_wrist_model(robot, m)) return spherical_configuration(robot, m, display);
  return Configuration{};  // words are defined for the closed-form families and spherical-wrist arms only
}

bool configuration_word_applies(const Robot& robot, ConfigurationWord word) {
  if (const IkFamily* f = ik_family_of(robot)) return f->word_applies(word);
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
