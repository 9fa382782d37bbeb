// VAL transformations: TRANS(x,y,z,o,a,t) with ZYZ Euler angles in degrees, and DECOMPOSE.
#pragma once
#include "asimov/collision/types.hpp"
#include <array>

namespace asimov::motion {

using Location = collision::Pose;  // 4x4 [R | p], p in mm
using Xyzoat = std::array<double, 6>;

Location trans(double x, double y, double z, double o, double a, double t);
Location trans(const Xyzoat& v);
// Canonical decomposition (dialect §4): o, t in (-180, 180], a in [0, 180].
Xyzoat decompose(const Location& loc);

}  // namespace asimov::motion
