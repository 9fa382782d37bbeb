// Synchronised minimum-time trapezoid (docs/kinematics.md §8): every axis follows q0 + sigma(t) * D_i
// with one normalised profile sigma(t), so all axes start and stop together. ACCEL scales the
// acceleration and the deceleration ramps separately (fractions a, d of each axis's A_i).
#pragma once
#include <span>

namespace asimov::motion {

struct ProfileAxis {
  double distance = 0;      // |D_i| (deg, mm, ...)
  double velocity = 1;      // V_i, already scaled by the speed factor (> 0)
  double acceleration = 1;  // A_i (> 0)
};

struct Profile {
  double x = 0;         // 1 / peak of sigma' [s] (x = U, or sqrt(k W) when triangular), after stretching
  double y = 0;         // acceleration time [s]
  double yd = 0;        // deceleration time [s] (= y unless ACCEL gives them different percentages)
  double duration = 0;  // T = x + (y + yd) / 2 [s]; 0 for a null motion

  double sigma(double t) const;    // normalised position in [0, 1], monotone in t
  double time_at(double s) const;  // inverse of sigma on [0, 1]
};

// ACCEL: the fractions (0, 1] of every axis's acceleration used to speed up and to slow down.
struct Ramps {
  double accel = 1;
  double decel = 1;
};

// Minimum-time profile over the axes, stretched uniformly in time to last at least
// `min_duration` seconds (DURATION; 0 = off). With ramps a, d: k = (1/a + 1/d) / 2,
// x = max(U, sqrt(k W)), y = W / (a x), yd = W / (d x) (a = d = 1: the symmetric trapezoid).
Profile plan_profile(std::span<const ProfileAxis> axes, double min_duration = 0, Ramps ramps = {});

// `p` stretched uniformly in time by k >= 1 (velocities / k, accelerations / k^2).
Profile stretched(const Profile& p, double k);

// A path followed with a profile: axis j is Q_j(sigma), sampled at sigma[i] (increasing, 0 ... 1)
// as q[i * axes + j]. Its acceleration is Q_j'' sigma'^2 + Q_j' sigma'' (curvature + profile).
struct SampledPath {
  std::span<const double> sigma;
  std::span<const double> q;
  int axes = 0;
};

// Largest |Q_j'' sigma'^2 + Q_j' sigma''| / acceleration[j] along the path under profile `p`,
// bounded per sample from finite differences of the samples (secant slopes, their change; the
// largest |Q''| of three neighbouring samples, the largest sigma'^2 and |sigma''| of the
// profile between them). Samples closer than 1e-3 in sigma are merged (finite-difference noise).
double path_acceleration_ratio(const Profile& p, const SampledPath& path, std::span<const double> acceleration);

// `p`, stretched when needed so that path_acceleration_ratio <= 1 (to 1e-9, rounding of an exactly
// bound profile; the stretch is exact: the ratio scales as 1/k^2).
Profile fit_path_acceleration(const Profile& p, const SampledPath& path, std::span<const double> acceleration);

}  // namespace asimov::motion
