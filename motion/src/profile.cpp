// docs/kinematics.md §8: U = max D/V, W = max D/A; trapezoid (x = U, y = W/U) when U^2 >= W, else
// triangle (x = y = sqrt W). Peak velocity D/x <= V and peak acceleration D/(xy) <= A per axis.
// ACCEL (ramps a, d): the ramps last y = W/(a x) and yd = W/(d x); the cruise x - (y + yd)/2
// must not be negative, so x = max(U, sqrt(k W)) with k = (1/a + 1/d)/2; T = x + (y + yd)/2.
#include "asimov/motion/profile.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace asimov::motion {

Profile plan_profile(std::span<const ProfileAxis> axes, double min_duration, Ramps ramps) {
  double u = 0, w = 0;
  for (const auto& a : axes) {
    u = std::max(u, std::abs(a.distance) / a.velocity);
    w = std::max(w, std::abs(a.distance) / a.acceleration);
  }
  Profile p;
  if (w > 0) {
    const double a = ramps.accel, d = ramps.decel;
    const double k = (1 / a + 1 / d) / 2;  // exactly 1 at 100 %, 100 %
    p.x = u * u >= k * w ? u : std::sqrt(k * w);
    p.y = w / (a * p.x);
    p.yd = w / (d * p.x);
  }
  p.duration = p.x + (p.y + p.yd) / 2;
  if (min_duration > p.duration) {
    if (p.duration > 0) {
      const double k = min_duration / p.duration;
      p.x *= k, p.y *= k, p.yd *= k;
    } else {  // null motion that must still last: a triangle of the requested length
      p.x = p.y = p.yd = min_duration / 2;
    }
    p.duration = min_duration;
  }
  return p;
}

Profile stretched(const Profile& p, double k) {
  if (!(k > 1) || p.duration <= 0) return p;
  Profile out = p;
  out.x *= k, out.y *= k, out.yd *= k, out.duration = out.x + (out.y + out.yd) / 2;
  return out;
}

double path_acceleration_ratio(const Profile& p, const SampledPath& path, std::span<const double> acceleration) {
  const int n = path.axes;
  if (p.duration <= 0 || n <= 0 || path.sigma.size() < 3) return 0;
  // Thinned sample indices: consecutive sigma at least kMinStep apart (the last one kept).
  constexpr double kMinStep = 1e-3;
  std::vector<std::size_t> idx{0};
  for (std::size_t i = 1; i < path.sigma.size(); ++i)
    if (path.sigma[i] - path.sigma[idx.back()] >= kMinStep || i + 1 == path.sigma.size()) idx.push_back(i);
  if (idx.size() >= 3 && path.sigma[idx.back()] - path.sigma[idx[idx.size() - 2]] < kMinStep)
    idx.erase(idx.end() - 2);  // the last kept interval too short: merge it into the one before
  const std::size_t m = idx.size();
  if (m < 3) return 0;
  const auto sg = [&](std::size_t k) { return path.sigma[idx[k]]; };
  const auto q = [&](std::size_t k, int j) { return path.q[idx[k] * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)]; };
  // Profile terms: sigma'^2 = min(1/x^2, 2 s/(x y), 2 (1 - s)/(x yd)); |sigma''| = 1/(x y) while
  // accelerating, 1/(x yd) while decelerating.
  const double s1 = p.y / (2 * p.x), s2 = p.yd / (2 * p.x);
  const auto max_rate2 = [&](double a, double b) {  // largest sigma'^2 on [a, b]
    return std::min({1 / (p.x * p.x), 2 * b / (p.x * p.y), 2 * (1 - a) / (p.x * p.yd)});
  };
  const auto max_accel = [&](double a, double b) {
    return std::max(a < s1 ? 1 / (p.x * p.y) : 0.0, b > 1 - s2 ? 1 / (p.x * p.yd) : 0.0);
  };
  double worst = 0;
  std::vector<double> slope(m - 1), curv(m);
  for (int j = 0; j < n; ++j) {
    const double lim = acceleration[static_cast<std::size_t>(j)];
    if (!(lim > 0)) continue;
    for (std::size_t k = 0; k + 1 < m; ++k) slope[k] = (q(k + 1, j) - q(k, j)) / (sg(k + 1) - sg(k));
    for (std::size_t k = 1; k + 1 < m; ++k) curv[k] = std::abs(2 * (slope[k] - slope[k - 1]) / (sg(k + 1) - sg(k - 1)));
    curv[0] = curv[1], curv[m - 1] = curv[m - 2];
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t lo = k > 0 ? k - 1 : 0, hi = k + 1 < m ? k + 1 : m - 1;
      const double qpp = std::max({curv[lo], curv[k], curv[hi]});
      const double qp = std::max(std::abs(slope[lo < m - 1 ? lo : m - 2]), std::abs(slope[k < m - 1 ? k : m - 2]));
      const double a = qpp * max_rate2(sg(lo), sg(hi)) + qp * max_accel(sg(lo), sg(hi));
      worst = std::max(worst, a / lim);
    }
  }
  return worst;
}

Profile fit_path_acceleration(const Profile& p, const SampledPath& path, std::span<const double> acceleration) {
  const double r = path_acceleration_ratio(p, path, acceleration);
  return r > 1 + 1e-9 ? stretched(p, std::sqrt(r)) : p;  // within rounding (an exactly bound profile): kept
}

double Profile::sigma(double t) const {
  if (duration <= 0 || t >= duration) return 1;
  if (t <= 0) return 0;
  if (t <= y) return t * t / (2 * x * y);
  if (t <= duration - yd) return (t - y / 2) / x;
  const double r = duration - t;
  return 1 - r * r / (2 * x * yd);
}

double Profile::time_at(double s) const {
  if (duration <= 0) return 0;
  s = std::clamp(s, 0.0, 1.0);
  const double s1 = y / (2 * x), s2 = yd / (2 * x);  // sigma at t = y, and 1 - sigma at t = T - yd
  if (s <= s1) return std::sqrt(2 * x * y * s);
  if (s <= 1 - s2) return x * s + y / 2;
  return duration - std::sqrt(2 * x * yd * (1 - s));
}

}  // namespace asimov::motion
