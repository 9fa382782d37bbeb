// Distance query, step 2 [ours]: a lower bound on the distance of two bodies' containers (or
// any two local axis-aligned boxes), in double, before any tree is built. The descent over the
// faces is distance_tree.hpp.
#pragma once
#include "minimax.hpp"

#include <cmath>

namespace asimov::collision {

// B's frame in A's for one pose (a = r b + t), and the lower bound of two node boxes.
struct DistanceNodeTest {
  Mat3 r, ar;   // rotation and |rotation|
  Vec3 t;
  double slack; // subtracted from every bound: the rounding of mapping boxes (eps_r of the pair)

  DistanceNodeTest(const Pose& a_from_b, double slack_mm)
      : r(a_from_b.linear()), ar(a_from_b.linear().cwiseAbs()), t(a_from_b.translation()), slack(slack_mm) {}

  // Boxes x (A's frame) and y (B's frame) as centre and half sides. Each is mapped into the
  // other's frame as the axis-aligned box holding it (centre R c + t, half |R| h); the distance
  // of two axis-aligned boxes is a lower bound on the distance of anything inside them, so the
  // larger of the two frames' values is one too.
  double lower_bound(const Vec3& xc, const Vec3& xh, const Vec3& yc, const Vec3& yh) const {
    const Vec3 yca = r * yc + t, yra = ar * yh;
    const Vec3 xcb = r.transpose() * (xc - t), xrb = ar.transpose() * xh;
    double s1 = 0, s2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double g1 = std::fabs(yca[k] - xc[k]) - xh[k] - yra[k];
      const double g2 = std::fabs(xcb[k] - yc[k]) - yh[k] - xrb[k];
      s1 += g1 > 0 ? g1 * g1 : 0.0;
      s2 += g2 > 0 ? g2 * g2 : 0.0;
    }
    return std::sqrt(s1 > s2 ? s1 : s2) - slack;
  }
};

}  // namespace asimov::collision
