#include "asimov/motion/location.hpp"

#include <cmath>
#include <numbers>

namespace asimov::motion {
namespace {
constexpr double kDeg = std::numbers::pi / 180;
// Angles reported in (-180, 180]: -180 becomes 180.
double canonical_deg(double rad) {
  double d = rad / kDeg;
  return d <= -180 ? d + 360 : d;
}
}  // namespace

Location trans(double x, double y, double z, double o, double a, double t) {
  Location loc = Location::Identity();
  loc.linear() = (Eigen::AngleAxisd(o * kDeg, collision::Vec3::UnitZ()) *
                   Eigen::AngleAxisd(a * kDeg, collision::Vec3::UnitY()) *
                   Eigen::AngleAxisd(t * kDeg, collision::Vec3::UnitZ()))
                      .toRotationMatrix();
  loc.translation() = collision::Vec3(x, y, z);
  return loc;
}

Location trans(const Xyzoat& v) { return trans(v[0], v[1], v[2], v[3], v[4], v[5]); }

Xyzoat decompose(const Location& loc) {
  const auto& r = loc.linear();
  const auto& p = loc.translation();
  const double s = std::hypot(r(0, 2), r(1, 2));
  double o, a, t;
  if (s > 1e-10) {
    a = std::atan2(s, r(2, 2));
    o = std::atan2(r(1, 2), r(0, 2));
    t = std::atan2(r(2, 1), -r(2, 0));
  } else if (r(2, 2) > 0) {
    o = 0, a = 0, t = std::atan2(r(1, 0), r(0, 0));
  } else {
    o = 0, a = std::numbers::pi, t = std::atan2(r(1, 0), -r(0, 0));
  }
  return {p.x(), p.y(), p.z(), canonical_deg(o), a / kDeg, canonical_deg(t)};
}

}  // namespace asimov::motion
