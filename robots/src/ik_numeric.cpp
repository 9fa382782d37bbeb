// Levenberg-Marquardt IK with projected joint limits and random restarts.
#include "asimov/robots/ik_numeric.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <random>

namespace asimov::robots {
namespace {
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Jac = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxJoints>;
using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, kMaxJoints>;

constexpr double kLambda0 = 1e-3;
constexpr double kLambdaMax = 1e8;

struct Chain {
  const Robot& robot;
  int n;
  JointVector lo, hi;     // internal limits
  double length;          // weight of the rotation error [mm/rad]
};

// Flange pose and weighted error e = [p* - p; L * log(R* R^T)] and Jacobian at internal q.
void evaluate(const Chain& c, const JointVector& q, const Pose& target, Vec6& e, Jac* jac) {
  Pose f = Pose::Identity();
  std::array<JointScrews, kMaxJoints> screws;
  for (int k = 0; k < c.n; ++k) f = joint_screws(c.robot, k, q[k], f, screws[static_cast<std::size_t>(k)]);
  e.head<3>() = target.translation() - f.translation();
  const Eigen::AngleAxisd r(target.linear() * f.linear().transpose());
  e.tail<3>() = c.length * r.angle() * r.axis();
  if (!jac) return;
  jac->resize(6, c.n);
  for (int k = 0; k < c.n; ++k) {  // own axis, plus those of coupled joints at their rates
    jac->col(k).setZero();
    const JointScrews& s = screws[static_cast<std::size_t>(k)];
    for (int i = 0; i < s.count; ++i) {
      const JointScrew& w = s.screw[static_cast<std::size_t>(i)];
      Vec6 col;
      if (w.type == JointType::prismatic) col << w.axis, Vec3::Zero();
      else col << w.axis.cross(f.translation() - w.point), c.length * w.axis;
      jac->col(k) += w.rate * col;
    }
  }
}

bool converged(const Chain& c, const Vec6& e, const NumericIkOptions& o) {
  return e.head<3>().norm() <= o.position_tol_mm && e.tail<3>().norm() / c.length <= o.rotation_tol_rad;
}

void clamp(const Chain& c, JointVector& q, bool limits) {
  if (!limits) return;
  for (int i = 0; i < c.n; ++i) q[i] = std::clamp(q[i], c.lo[i], c.hi[i]);
}

// One LM descent from q (modified in place). Returns iterations used; `e` holds the final error.
int descend(const Chain& c, const Pose& target, const NumericIkOptions& o, JointVector& q, Vec6& e) {
  Jac jac;
  evaluate(c, q, target, e, &jac);
  double cost = e.squaredNorm();
  double lambda = kLambda0;
  int it = 0;
  int stalls = 0;
  while (it < o.max_iterations && !converged(c, e, o)) {
    ++it;
    const Square jtj = jac.transpose() * jac;
    Square a = jtj;
    for (int i = 0; i < c.n; ++i) a(i, i) += lambda * (jtj(i, i) + 1e-9);
    const JointVector step = a.ldlt().solve(jac.transpose() * e);
    JointVector trial = q + step;
    clamp(c, trial, o.respect_limits);
    Vec6 e_trial;
    Jac jac_trial;
    evaluate(c, trial, target, e_trial, &jac_trial);
    const double cost_trial = e_trial.squaredNorm();
    if (cost_trial < cost) {
      stalls = cost_trial > 0.999 * cost ? stalls + 1 : 0;
      q = trial, e = e_trial, jac = jac_trial, cost = cost_trial;
      lambda = std::max(lambda / 10, 1e-12);
    } else {
      lambda *= 10;
      ++stalls;
    }
    if (lambda > kLambdaMax || stalls > 8) break;  // stuck in a local minimum or on a limit
  }
  return it;
}
}  // namespace

void pose_error(const Robot& robot, const JointVector& display, const Pose& target, double& position_mm,
                double& rotation_rad) {
  const Pose f = flange_pose(robot, display);
  position_mm = (f.translation() - target.translation()).norm();
  rotation_rad = Eigen::AngleAxisd(target.linear() * f.linear().transpose()).angle();
}

NumericIkResult solve_numeric(const Robot& robot, const Pose& flange, const JointVector& seed,
                              const NumericIkOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  Chain c{robot, robot.joint_count(), {}, {}, 0};
  JointVector lo = robot.lower, hi = robot.upper;  // widened by the description's precision
  for (int k = 0; k < c.n; ++k) lo[k] = limit_low(robot, k), hi[k] = limit_high(robot, k);
  const JointVector a = display_to_dh(robot, lo), b = display_to_dh(robot, hi);
  c.lo = a.cwiseMin(b), c.hi = a.cwiseMax(b);
  double reach = 0;
  for (int k = 0; k < c.n; ++k) reach += link_offset_bound(robot, k);
  c.length = std::max(reach / 2, 1.0);
  NumericIkResult res;
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u(0, 1);
  JointVector q = display_to_dh(robot, seed.size() == c.n ? seed : ready_joints(robot));
  clamp(c, q, o.respect_limits);
  double best = std::numeric_limits<double>::infinity();
  JointVector best_q = q;
  for (int attempt = 0; attempt < o.max_attempts; ++attempt) {
    if (attempt > 0) {
      if (o.timeout_s > 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > o.timeout_s)
        break;
      for (int i = 0; i < c.n; ++i) q[i] = c.lo[i] + u(rng) * (c.hi[i] - c.lo[i]);
    }
    Vec6 e;
    res.iterations += descend(c, flange, o, q, e);
    res.attempts = attempt + 1;
    if (e.squaredNorm() < best) best = e.squaredNorm(), best_q = q;
    if (converged(c, e, o)) {
      res.success = true;
      break;
    }
  }
  res.joints = dh_to_display(robot, best_q);
  pose_error(robot, res.joints, flange, res.position_error_mm, res.rotation_error_rad);
  return res;
}

}  // namespace asimov::robots
