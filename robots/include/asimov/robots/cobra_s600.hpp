// The built-in Adept Cobra s600 SCARA (docs/robots.md "cobra_s600"): a chain J1, J2 revolute about
// +Z, J3 the quill (prismatic, displayed mm, positive = down, 0..210), J4 the quill roll about the
// downward quill axis; flange Z pointing down (a V+ SCARA location has pitch 180). Geometry,
// limits and speeds of the adept_experimental description, whose V+ driver fixes the joint
// display (J3 = -1000 x its prismatic joint). World frame: the base mounting surface, Z up.
#pragma once
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

Robot cobra_s600();

namespace cobra {
constexpr double h1 = 342, l1 = 325, l2 = 275, quill = 45;  // [mm]: J1 flange height, links, quill offset
}  // namespace cobra

}  // namespace asimov::robots
