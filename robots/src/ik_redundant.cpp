// The nearest-reference IK of redundant arms (ik_redundant.hpp). Each iteration takes the
// point of the linearised constraint J dq = e nearest the reference: q+ = q_ref + J^+ (e + J (q -
// q_ref)), the Gauss-Newton step of min |q - q_ref|^2 s.t. FK(q) = T. Its fixed points are the
// poses' solutions whose offset from the reference is orthogonal to the self-motion (null space of
// J): the first-order condition of the minimum, which depends on the pose and the reference only.
#include "asimov/robots/ik_redundant.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>

namespace asimov::robots {
namespace {
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Jac = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxJoints>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

constexpr int kMaxIterations = 200;
constexpr double kStepTol = 1e-13;      // [rad] (scaled units): converged when a step is below this
constexpr double kMaxStep = 0.25;       // [rad]: one iteration moves no joint further (stays in the basin)
constexpr double kPositionTol = 1e-6;   // [mm], as every solver's acceptance
constexpr double kRotationTol = 1e-9;   // [rad]

// Error e = [p* - p; L log(R* R^T)] and the geometric Jacobian at internal joints q, columns of
// prismatic joints scaled by L (their variable is q / L, so that mm and rad weigh alike).
void evaluate(const Robot& robot, const JointVector& q, const Pose& target, double length, Vec6& e, Jac& jac) {
  const int n = robot.joint_count();
  Pose f = Pose::Identity();
  std::array<JointScrews, kMaxJoints> screws;
  for (int k = 0; k < n; ++k) f = joint_screws(robot, k, q[k], f, screws[static_cast<std::size_t>(k)]);
  e.head<3>() = target.translation() - f.translation();
  const Eigen::AngleAxisd r(target.linear() * f.linear().transpose());
  e.tail<3>() = length * r.angle() * r.axis();
  jac.resize(6, n);
  for (int k = 0; k < n; ++k) {  // own axis, plus those of coupled joints at their rates
    jac.col(k).setZero();
    const JointScrews& s = screws[static_cast<std::size_t>(k)];
    for (int i = 0; i < s.count; ++i) {
      const JointScrew& w = s.screw[static_cast<std::size_t>(i)];
      Vec6 col;
      if (w.type == JointType::prismatic) col << length * w.axis, Vec3::Zero();
      else col << w.axis.cross(f.translation() - w.point), length * w.axis;
      jac.col(k) += (robot.prismatic(k) ? length : 1.0) * w.rate * col / (w.type == JointType::prismatic ? length : 1.0);
    }
  }
}
}  // namespace

IkResult solve_nearest_reference(const Robot& robot, const Pose& flange, const JointVector& seed,
                                 const JointVector& reference) {
  const int n = robot.joint_count();
  IkResult res;
  double reach = 0;
  for (int k = 0; k < n; ++k) reach += link_offset_bound(robot, k);
  const double length = std::max(reach / 2, 1.0);
  // Scaled internal variables x: revolute rad, prismatic mm / length.
  auto to_x = [&](const JointVector& display) {
    JointVector x = display_to_dh(robot, display);
    for (int k = 0; k < n; ++k)
      if (robot.prismatic(k)) x[k] /= length;
    return x;
  };
  auto to_q = [&](const JointVector& x) {
    JointVector q = x;
    for (int k = 0; k < n; ++k)
      if (robot.prismatic(k)) q[k] *= length;
    return q;
  };
  if (seed.size() != n || reference.size() != n || !seed.allFinite() || !reference.allFinite()) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  const JointVector x_ref = to_x(reference);
  JointVector x = to_x(seed);
  Vec6 e;
  Jac jac;
  bool converged = false;
  for (int it = 0; it < kMaxIterations && !converged; ++it) {
    evaluate(robot, to_q(x), flange, length, e, jac);
    const Mat6 jjt = jac * jac.transpose();
    const Eigen::LDLT<Mat6> ldlt(jjt + Mat6::Identity() * (1e-14 * std::max(1.0, jjt.trace())));
    const JointVector offset = x - x_ref;
    JointVector step = x_ref + jac.transpose() * ldlt.solve(e + jac * offset) - x;
    const double big = step.cwiseAbs().maxCoeff();
    if (!(big < 1e3)) break;  // singular: the step has no bound
    if (big > kMaxStep) step *= kMaxStep / big;
    x += step;
    converged = big <= kStepTol;
  }
  evaluate(robot, to_q(x), flange, length, e, jac);
  if (!(e.head<3>().norm() <= kPositionTol && e.tail<3>().norm() / length <= kRotationTol)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  const JointVector q = dh_to_display(robot, to_q(x));
  for (int k = 0; k < n; ++k)
    if (!(q[k] >= limit_low(robot, k) && q[k] <= limit_high(robot, k))) {
      res.status = IkStatus::joint_limit;
      res.joint = k;
      res.value = q[k];
      return res;
    }
  res.joints = q;
  return res;
}

IkResult solve_line_ik(const Robot& robot, const Pose& flange, const JointVector& seed, const JointVector& reference,
                       const Configuration& want) {
  if (robot.joint_count() <= 6) return solve_ik(robot, flange, seed, want, false);
  return solve_nearest_reference(robot, flange, seed, reference);
}

}  // namespace asimov::robots
