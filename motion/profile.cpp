// kinematics.md §8: U = max D/V, W = max D/A; trapezoid (x = U, y = W/U) when U^2 >= W, else
// triangle (x = y = sqrt W). Peak velocity D/x <= V and peak acceleration D/(xy) <= A per axis.
#include "motion/profile.hpp"

#include <algorithm>
#include <cmath>

namespace asimov::motion {

Profile plan_profile(std::span<const ProfileAxis> axes, double min_duration) {
  double u = 0, w = 0;
  for (const auto& a : axes) {
    u = std::max(u, std::abs(a.distance) / a.velocity);
    w = std::max(w, std::abs(a.distance) / a.acceleration);
  }
  Profile p;
  if (w > 0) {
    if (u * u >= w) {
      p.x = u, p.y = w / u;
    } else {
      p.x = p.y = std::sqrt(w);
    }
  }
  p.duration = p.x + p.y;
  if (min_duration > p.duration) {
    if (p.duration > 0) {
      const double k = min_duration / p.duration;
      p.x *= k, p.y *= k;
    } else {  // null motion that must still last: a triangle of the requested length
      p.x = p.y = min_duration / 2;
    }
    p.duration = min_duration;
  }
  return p;
}

double Profile::sigma(double t) const {
  if (duration <= 0 || t >= duration) return 1;
  if (t <= 0) return 0;
  if (t <= y) return t * t / (2 * x * y);
  if (t <= x) return (t - y / 2) / x;
  const double r = duration - t;
  return 1 - r * r / (2 * x * y);
}

double Profile::time_at(double s) const {
  if (duration <= 0) return 0;
  s = std::clamp(s, 0.0, 1.0);
  const double s1 = y / (2 * x);  // sigma at t = y, and 1 - sigma at t = x
  if (s <= s1) return std::sqrt(2 * x * y * s);
  if (s <= 1 - s1) return x * s + y / 2;
  return duration - std::sqrt(2 * x * y * (1 - s));
}

}  // namespace asimov::motion
