// A closed-form IK family: a chain shape with its own solver and its own reading of the
// configuration words (docs/kinematics.md). The rows of arm_families.def list them; solve_ik,
// configuration_of and configuration_word_applies dispatch through ik_family_of.
#pragma once
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_puma.hpp"
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

struct IkFamily {
  const char* name;
  // Recognises the chain from its joint axes and origins (called for every solve: keep it cheap
  // or cache, as the SCARA family does).
  bool (*matches)(const Robot& robot);
  // Solution in configuration `want`, joints nearest `current` (display) inside the limits;
  // J6 (the last revolute joint) in (-180, 180] when `single`. FK-checked.
  IkResult (*solve)(const Robot& robot, const Pose& flange, const JointVector& current, const Configuration& want,
                    bool single);
  Configuration (*configuration)(const Robot& robot, const JointVector& display);
  bool (*word_applies)(ConfigurationWord word);
  // Position-singularity margins of a flange position (reach_margins, ik.hpp); null when the
  // family has no closed-form test (its lines get the joint-jump test only).
  std::optional<ReachMargins> (*margins)(const Robot& robot, const Vec3& flange_position) = nullptr;
};

#define ASIMOV_IK_FAMILY(NAME) extern const IkFamily NAME##_family;
#include "arm_families.def"

// The family of `robot`: the first row of arm_families.def that matches; null for none.
const IkFamily* ik_family_of(const Robot& robot);

inline bool every_word_applies(ConfigurationWord) { return true; }

}  // namespace asimov::robots
