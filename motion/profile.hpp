// Synchronised minimum-time trapezoid (kinematics.md §8): every axis follows q0 + sigma(t) * D_i
// with one normalised profile sigma(t), so all axes start and stop together.
#pragma once
#include <span>

namespace asimov::motion {

struct ProfileAxis {
  double distance = 0;      // |D_i| (deg, mm, ...)
  double velocity = 1;      // V_i, already scaled by the speed factor (> 0)
  double acceleration = 1;  // A_i (> 0)
};

struct Profile {
  double x = 0;         // cruise end [s] (x = U, or sqrt(W) when triangular), after stretching
  double y = 0;         // blend time [s]
  double duration = 0;  // T = x + y [s]; 0 for a null motion

  double sigma(double t) const;    // normalised position in [0, 1], monotone in t
  double time_at(double s) const;  // inverse of sigma on [0, 1]
};

// Minimum-time profile over the axes, stretched uniformly in time to last at least
// `min_duration` seconds (DURATION; 0 = off).
Profile plan_profile(std::span<const ProfileAxis> axes, double min_duration = 0);

}  // namespace asimov::motion
