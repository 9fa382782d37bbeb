// Synchronised minimum-time trapezoid (docs/kinematics.md §8).
#include "asimov/motion/interpolation.hpp"
#include "asimov/motion/profile.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <vector>
#include <catch2/catch.hpp>
#include <random>

using namespace asimov::motion;

TEST_CASE("profile: duration formula, trapezoid and triangle", "[profile]") {
  // One axis, D = 90 deg, V = 90 deg/s, A = 360: U = 1, W = 0.25, trapezoid T = 1.25.
  std::array<ProfileAxis, 1> a{{{90, 90, 360}}};
  Profile p = plan_profile(a);
  CHECK(p.x == Approx(1));
  CHECK(p.y == Approx(0.25));
  CHECK(p.duration == Approx(1.25));
  // Short move: D = 10, U = 1/9, W = 1/36 > U^2: triangle, T = 2 sqrt(W) = 1/3.
  a[0].distance = 10;
  p = plan_profile(a);
  CHECK(p.x == p.y);
  CHECK(p.duration == Approx(1.0 / 3));
  // DURATION stretches uniformly.
  p = plan_profile(a, 2.0);
  CHECK(p.duration == Approx(2.0));
  CHECK(p.x / p.y == Approx(1));
  // Null motion.
  a[0].distance = 0;
  CHECK(plan_profile(a).duration == 0);
  CHECK(plan_profile(a).sigma(0) == 1);
}

TEST_CASE("profile: limits respected, sigma monotone, inverse exact", "[profile][random]") {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> dist(0, 300), vel(5, 200), acc(10, 800), dur(0, 3);
  for (int n = 0; n < 500; ++n) {
    std::array<ProfileAxis, 6> axes;
    for (auto& ax : axes) ax = {dist(rng), vel(rng), acc(rng)};
    const double min_d = n % 3 == 0 ? dur(rng) : 0;
    const Profile p = plan_profile(axes, min_d);
    REQUIRE(p.duration > 0);
    CHECK(p.duration >= min_d - 1e-12);
    // Numerical peak velocity / acceleration per axis from sigma(t).
    const int steps = 2000;
    const double h = p.duration / steps;
    double vmax = 0, amax = 0, prev = 0, prev_v = 0, inv_err = 0;
    bool monotone = true;
    for (int i = 1; i <= steps; ++i) {
      const double s = p.sigma(i * h);
      monotone = monotone && s >= prev;
      const double v = (s - prev) / h;
      vmax = std::max(vmax, v);
      if (i > 1) amax = std::max(amax, std::abs(v - prev_v) / h);
      prev = s, prev_v = v;
      if (s > 1e-6 && s < 1 - 1e-6) inv_err = std::max(inv_err, std::abs(p.time_at(s) - i * h));
    }
    CHECK(monotone);
    CHECK(inv_err < 1e-9);
    CHECK(prev == Approx(1));
    for (const auto& ax : axes) {
      CHECK(ax.distance / p.x <= ax.velocity * (1 + 1e-12));               // analytic peak velocity
      CHECK(ax.distance / (p.x * p.y) <= ax.acceleration * (1 + 1e-12));  // analytic peak accel
      CHECK(vmax * ax.distance <= ax.velocity * (1 + 1e-9));
      CHECK(amax * ax.distance <= ax.acceleration * (1 + 1e-2));  // finite differences
    }
  }
}

TEST_CASE("straight-line interpolation: slerp, shortest arc, orthonormal", "[interpolation]") {
  const Location a = trans(0, 0, 0, 0, 0, 0), b = trans(100, 0, 0, 0, 90, 0);
  const LinePath path = make_line(a, b);
  CHECK(path.length == Approx(100));
  CHECK(path.angle_deg() == Approx(90));
  const Location m = line_pose(path, 0.5);
  CHECK(m.translation().x() == Approx(50));
  CHECK(Eigen::AngleAxisd(a.linear().transpose() * m.linear()).angle() == Approx(3.14159265358979 / 4));
  CHECK((m.linear() * m.linear().transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
  CHECK(line_pose(path, 1).isApprox(b, 1e-12));
  // Shortest arc: 350 deg of yaw is a 10 deg motion.
  const LinePath p2 = make_line(trans(0, 0, 0, 0, 0, 0), trans(0, 0, 0, 350, 0, 0));
  CHECK(p2.angle_deg() == Approx(10));
  // Identical orientations: linear fallback.
  const LinePath p3 = make_line(a, trans(10, 0, 0, 0, 0, 0));
  CHECK(line_pose(p3, 0.3).linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
}

TEST_CASE("profile: path acceleration: the ratio scales as 1/k^2 and fitting brings it to 1", "[profile]") {
  constexpr double kPi = std::numbers::pi;
  // A circle-like joint path q = (cos 2 pi s, sin 2 pi s) * 100: |Q''| = 400 pi^2 everywhere.
  const int n = 2001;
  std::vector<double> s(n), q(2 * n);
  for (int i = 0; i < n; ++i) {
    s[static_cast<std::size_t>(i)] = static_cast<double>(i) / (n - 1);
    q[static_cast<std::size_t>(2 * i)] = 100 * std::cos(2 * kPi * s[static_cast<std::size_t>(i)]);
    q[static_cast<std::size_t>(2 * i + 1)] = 100 * std::sin(2 * kPi * s[static_cast<std::size_t>(i)]);
  }
  const SampledPath path{s, q, 2};
  const std::array<double, 2> accel{50, 50};
  std::array<ProfileAxis, 2> axes{{{200 * kPi, 1000, 50}, {200 * kPi, 1000, 50}}};  // slope bound only
  const Profile p = plan_profile(axes);
  const double r = path_acceleration_ratio(p, path, accel);
  // Cruise speed 1/x: the curvature term alone is 400 pi^2 / x^2 over the limit 50.
  CHECK(r >= 400 * kPi * kPi / (p.x * p.x) / 50 * (1 - 1e-3));
  CHECK(r > 1);  // the slope-only profile is too fast for the curvature
  const Profile fit = fit_path_acceleration(p, path, accel);
  CHECK(fit.duration == Approx(p.duration * std::sqrt(r)).epsilon(1e-12));
  CHECK(path_acceleration_ratio(fit, path, accel) == Approx(1).epsilon(1e-9));
  CHECK(path_acceleration_ratio(stretched(p, 2), path, accel) == Approx(r / 4).epsilon(1e-9));
  // A straight joint path (no curvature) keeps its profile.
  for (int i = 0; i < n; ++i) q[static_cast<std::size_t>(2 * i)] = q[static_cast<std::size_t>(2 * i + 1)] = 10 * s[static_cast<std::size_t>(i)];
  std::array<ProfileAxis, 2> straight{{{10, 100, 50}, {10, 100, 50}}};
  const Profile ps = plan_profile(straight);
  CHECK(path_acceleration_ratio(ps, path, accel) <= 1 + 1e-9);
  CHECK(fit_path_acceleration(ps, path, accel).duration == ps.duration);
}

TEST_CASE("profile: ACCEL ramps scale the acceleration and the deceleration separately", "[profile]") {
  // D = 100, V = 100, A = 100: U = W = 1. Ramps 50 % / 100 %: k = 1.5 > U^2, so a triangle with
  // x = sqrt(1.5), y = W / (0.5 x), yd = W / x; T = x + (y + yd) / 2.
  const ProfileAxis axis{100, 100, 100};
  const Profile p = plan_profile(std::span(&axis, 1), 0, {0.5, 1});
  CHECK(p.x == Approx(std::sqrt(1.5)));
  CHECK(p.y == Approx(1 / (0.5 * std::sqrt(1.5))));
  CHECK(p.yd == Approx(1 / std::sqrt(1.5)));
  CHECK(p.duration == Approx(p.x + (p.y + p.yd) / 2));
  CHECK(axis.distance / (p.x * p.y) == Approx(50));   // peak acceleration: 50 % of A
  CHECK(axis.distance / (p.x * p.yd) == Approx(100)); // peak deceleration: all of A
  CHECK(axis.distance / p.x <= axis.velocity * (1 + 1e-12));
  // sigma is continuous and monotone, time_at its inverse, also across both ramp ends.
  double prev = 0;
  for (int i = 1; i <= 1000; ++i) {
    const double t = p.duration * i / 1000, s = p.sigma(t);
    CHECK(s >= prev);
    CHECK(s - prev < 0.01);
    CHECK(p.time_at(s) == Approx(t).margin(1e-9));
    prev = s;
  }
  CHECK(p.sigma(p.duration) == 1);
  // 100 %, 100 %: the symmetric trapezoid exactly.
  const Profile q = plan_profile(std::span(&axis, 1), 0, {1, 1});
  const Profile r = plan_profile(std::span(&axis, 1));
  CHECK(q.x == r.x);
  CHECK(q.y == r.y);
  CHECK(q.yd == r.y);
  CHECK(q.duration == r.duration);
}
