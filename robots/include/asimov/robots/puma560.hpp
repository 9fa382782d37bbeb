// The built-in PUMA 560: Corke's standard DH table (mm), display mapping, limits set A,
// default velocity/acceleration limits and coarse convex link bodies "link0".."link6".
//
// Display -> DH mapping (derived, see robots/README.md): theta_dh = sign * display, zero
// offsets, signs (+1, -1, -1, +1, -1, +1) for J1..J6.
#pragma once
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

Robot puma560();

namespace puma {
constexpr double a2 = 431.8, a3 = 20.3, d3 = 150.05, d4 = 431.8;  // [mm]
}  // namespace puma

}  // namespace asimov::robots
