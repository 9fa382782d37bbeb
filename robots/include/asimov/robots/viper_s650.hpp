// The built-in Adept Viper s650 (docs/robots.md "viper_s650"): standard DH fitted to the
// closed-form FK of ViSP's vpViper650 (which reads V+ joint values from the controller), V+
// joint display convention, Adept's joint limits and maximum joint speeds, coarse link bodies
// "link0".."link6". World frame: the base mounting surface, Z up along J1.
//
// theta = (J1, J2, J3 + 180, J4, J5, J6 + 180) [deg]; d = (335, 0, 0, 295, 0, 80),
// a = (75, 270, 90, 0, 0, 0) [mm], alpha = (-90, 0, -90, 90, -90, 0) [deg]. At all joints 0 the
// upper arm is horizontal forward (+X), the forearm vertical, the flange frame the world's axes.
#pragma once
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

Robot viper_s650();

namespace viper {
constexpr double d1 = 335, a1 = 75, a2 = 270, a3 = 90, d4 = 295, d6 = 80;  // [mm]
}  // namespace viper

}  // namespace asimov::robots
