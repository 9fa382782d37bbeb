// Numeric inverse kinematics for any serial arm: Levenberg-Marquardt on the weighted pose error
// (position [mm], rotation [rad] x a characteristic length), joint limits by projection, random
// restarts from a fixed seed. No heap: fixed-capacity Eigen matrices.
#pragma once
#include "asimov/robots/robot.hpp"
#include <cstdint>

namespace asimov::robots {

struct NumericIkOptions {
  double position_tol_mm = 1e-6;   // success: |p - p*| <= this
  double rotation_tol_rad = 1e-9;  //          and the angle of R*^T R <= this
  int max_iterations = 60;         // per attempt
  int max_attempts = 30;           // the seed, then random restarts
  double timeout_s = 0;            // wall-clock budget over all attempts; 0 = none
  bool respect_limits = true;      // false: limits ignored (used to tell "limit" from "reach")
  std::uint64_t seed = 20261128;   // restarts are reproducible
};

struct NumericIkResult {
  bool success = false;
  JointVector joints;              // display values of the best solution found
  int iterations = 0;              // over all attempts
  int attempts = 0;                // 1 = converged from the seed
  double position_error_mm = 0;    // of `joints`
  double rotation_error_rad = 0;
};

// Solves FK(q) = flange (robot frame) from `seed` (display; empty: READY).
NumericIkResult solve_numeric(const Robot& robot, const Pose& flange, const JointVector& seed,
                              const NumericIkOptions& options = {});

// Position [mm] and rotation angle [rad] between the flange at `display` and `target`.
void pose_error(const Robot& robot, const JointVector& display, const Pose& target, double& position_mm,
                double& rotation_rad);

}  // namespace asimov::robots
