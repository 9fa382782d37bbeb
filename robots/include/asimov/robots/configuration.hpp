// VAL configuration words for a PUMA-type arm.
#pragma once
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

struct Configuration {
  bool righty = true;  // RIGHTY / LEFTY
  bool above = true;   // ABOVE / BELOW
  bool noflip = true;  // NOFLIP / FLIP (displayed J5 >= 0)
  bool operator==(const Configuration&) const = default;
};

// Requests pending for the next joint motion to a transformation; unset fields keep the current.
struct ConfigurationRequest {
  int righty = -1, above = -1, noflip = -1;  // -1 unset, 0 false, 1 true
  bool single = true;                        // SINGLE (J6 in (-180,180]) / MULTIPLE
};

// Configuration actually reached by a PUMA-type arm at `display` joints (docs/kinematics.md §6):
// A 6R chain with J1 _|_ J2 || J3 and a spherical wrist (spherical_wrist_model) gets the same
// words from the same geometry (forward sign taken from its zero pose, where the wrist centre is
// in front; ABOVE = elbow on the J1-axis side of the shoulder-wrist line).
// Other arms (numeric IK) have no configuration words: the default RIGHTY ABOVE NOFLIP.
// RIGHTY iff V >= 0, ABOVE iff sigma_s * wrap(theta2 - atan2(pz, V)) >= 0, NOFLIP iff J5 >= 0.
Configuration configuration_of(const Robot& robot, const JointVector& display);

// The three pairs of words: LEFTY/RIGHTY (arm), ABOVE/BELOW (elbow), FLIP/NOFLIP (wrist).
enum class ConfigurationWord { arm, elbow, wrist };

// Whether requests of `word` mean anything for the robot: all three for the PUMA, Viper-type
// and spherical-wrist 6R arms; only `arm` (the elbow) for a SCARA; none for other arms (numeric
// IK, requests ignored). The interpreter warns once when a program uses a word that does not.
bool configuration_word_applies(const Robot& robot, ConfigurationWord word);

// `current` overridden by the set fields of `request`.
Configuration requested_configuration(const Configuration& current, const ConfigurationRequest& request);

}  // namespace asimov::robots
