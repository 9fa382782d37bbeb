#include "asimov/motion/sampler.hpp"

#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_redundant.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace asimov::motion {
namespace {
using robots::JointVector;

constexpr int kMaxRefineDepth = 6;  // subdivision rounds of one interval before giving up
constexpr int kMaxSplits = 4096;    // sub-intervals per round

struct LineContext {
  const robots::Robot& robot;
  std::span<const robots::BodyReach> reach;
  const LineRequest& req;
  Location base_inv;
  Location tool_inv;
  double limit;  // kLineSafety * step_mm
};

LineStatus fail(LinePlan& plan, LineStatus st, double s) {
  plan.status = st;
  plan.fail_fraction = s;
  return st;
}

LineStatus singular(LinePlan& plan, SingularityKind kind, double s) {
  plan.singularity = kind;
  return fail(plan, LineStatus::singularity, s);
}

// The arm family's position-singularity margins at the flange pose of sample s (arms without
// them: joint jumps only).
LineStatus check_margins(const LineContext& c, const Location& flange, double s, LinePlan& plan) {
  const std::optional<robots::ReachMargins> m = robots::reach_margins(c.robot, flange.translation());
  if (!m) return LineStatus::ok;
  if (m->shoulder_mm < kShoulderMarginMm) return singular(plan, SingularityKind::shoulder, s);
  if (m->elbow_mm < kElbowMarginMm) return singular(plan, SingularityKind::elbow, s);
  return LineStatus::ok;
}

// Solves and checks one sample; `prev` is the joint reference (nearest equivalents, kept J4).
LineStatus solve_sample(const LineContext& c, double s, const JointVector& prev, JointVector& out, LinePlan& plan) {
  const Location flange = c.base_inv * line_pose(c.req.path, s) * c.tool_inv;
  // Redundant arms: the solution nearest the line's start, whatever the step (ik_redundant.hpp).
  const robots::IkResult ik = robots::solve_line_ik(c.robot, flange, prev, c.req.start, c.req.config);
  if (ik.status == robots::IkStatus::ok) {
    plan.ik_residual.merge(pose_error(robots::flange_pose(c.robot, ik.joints), flange));
    ++plan.ik_solves;
  }
  if (ik.status == robots::IkStatus::out_of_reach) return fail(plan, LineStatus::out_of_reach, s);
  if (check_margins(c, flange, s, plan) != LineStatus::ok) return plan.status;
  if (ik.status == robots::IkStatus::joint_limit) {
    plan.joint = ik.joint, plan.value = ik.value;
    // A limit hit by a sudden jump (e.g. J4 turning 180 deg through the wrist singularity) is
    // reported as what it is.
    if (std::abs(ik.value - prev[ik.joint]) > kMaxJointJumpDeg) {
      plan.value = std::abs(ik.value - prev[ik.joint]);
      return singular(plan, SingularityKind::joint_jump, s);
    }
    return fail(plan, LineStatus::joint_limit, s);
  }
  for (int i = 0; i < ik.joints.size(); ++i) {
    const double jump = std::abs(ik.joints[i] - prev[i]);
    if (jump > kMaxJointJumpDeg) {
      plan.joint = i, plan.value = jump;
      return singular(plan, SingularityKind::joint_jump, s);
    }
  }
  out = ik.joints;
  return LineStatus::ok;
}

// ceil(x) as a number of intervals, at least 1 and at most 2^30 so that the conversion to int
// is defined when x is huge or infinite (an absurdly small step_mm; 2^30 poses take hours).
int interval_count(double x) {
  constexpr double kMax = 1073741824.0;
  const double c = std::ceil(x);
  return c >= kMax ? static_cast<int>(kMax) : c >= 1 ? static_cast<int>(c) : 1;
}

// Appends samples strictly inside (a, b] so that the bound between neighbours is <= limit.
LineStatus refine(const LineContext& c, const LineSample& a, const LineSample& b, int depth, LinePlan& plan) {
  double body_max = 0;
  const double d = max_body_displacement(c.reach, b.joints - a.joints, c.req.pairs, &body_max);
  if (d <= c.limit) {
    plan.samples.push_back(b);
    plan.samples.back().bound_mm = body_max;
    return LineStatus::ok;
  }
  if (depth >= kMaxRefineDepth) return singular(plan, SingularityKind::unresolved, b.s);
  const int m = std::clamp(interval_count(d / c.limit), 2, kMaxSplits);
  LineSample prev = a;
  for (int i = 1; i <= m; ++i) {
    LineSample next;
    if (i == m) {
      next = b;
    } else {
      next.s = a.s + (b.s - a.s) * i / m;
      if (solve_sample(c, next.s, prev.joints, next.joints, plan) != LineStatus::ok) return plan.status;
    }
    if (refine(c, prev, next, depth + 1, plan) != LineStatus::ok) return plan.status;
    prev = next;
  }
  return LineStatus::ok;
}
}  // namespace

double max_body_displacement(std::span<const robots::BodyReach> reach, const JointVector& delta,
                             std::span<const BodyPair> pairs, double* body_max) {
  constexpr std::size_t kMaxBodies = 32;
  std::array<double, kMaxBodies> d{};
  double m = 0;
  for (std::size_t k = 0; k < reach.size(); ++k) {
    const double dk = robots::max_displacement(reach[k], delta);
    if (k < kMaxBodies) d[k] = dk;
    m = std::max(m, dk);
  }
  if (body_max) *body_max = m;
  for (const auto& [a, b] : pairs)
    if (std::size_t{std::max(a, b)} < std::min(reach.size(), kMaxBodies)) m = std::max(m, d[a] + d[b]);
  return m;
}

void PoseError::merge(const PoseError& o) {
  position_mm = std::max(position_mm, o.position_mm);
  rotation_rad = std::max(rotation_rad, o.rotation_rad);
}

PoseError pose_error(const Location& a, const Location& b) {
  // |R_a - R_b|_F = 2 sqrt(2) sin(theta / 2): exact for small angles, unlike acos of the trace.
  const double chord = (a.linear() - b.linear()).norm() / (2 * std::sqrt(2.0));
  return {(a.translation() - b.translation()).norm(), 2 * std::asin(std::min(1.0, chord))};
}

double gap_allowance(double gap_mm, double clearance_mm, double step_mm) {
  return std::max({clearance_mm, step_mm, gap_mm - clearance_mm});
}

double pair_displacement(std::span<const robots::BodyReach> reach, const GapPair& p, const JointVector& delta) {
  if (p.a < 0 || p.b < 0) {
    const int k = std::max(p.a, p.b);
    return k < 0 ? 0.0 : robots::max_displacement(reach[static_cast<std::size_t>(k)], delta);
  }
  if (p.link_a < 0 || p.link_b < 0)  // a body with a motion of its own (a follower of an arm joint)
    return robots::max_displacement(reach[static_cast<std::size_t>(p.a)], delta) +
           robots::max_displacement(reach[static_cast<std::size_t>(p.b)], delta);
  const bool a_inner = p.link_a <= p.link_b;
  const int inner = a_inner ? p.link_a : p.link_b, outer = a_inner ? p.link_b : p.link_a;
  const robots::BodyReach& r = reach[static_cast<std::size_t>(a_inner ? p.b : p.a)];
  constexpr double kDeg = std::numbers::pi / 180;  // display degrees, as robots::max_displacement
  double d = 0;
  for (int j = inner; j < outer && j < delta.size(); ++j) d += std::abs(delta[j]) * kDeg * r.radius[static_cast<std::size_t>(j)];
  return d;
}

int gap_intervals(std::span<const double> pair_mm, std::span<const GapPair> pairs, int remaining) {
  double k = remaining;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (pair_mm[i] > 0) k = std::min(k, std::floor(pairs[i].allow_mm / pair_mm[i]));
  return std::clamp(static_cast<int>(k), 1, std::max(1, remaining));
}

std::size_t gap_next_sample(std::span<const robots::BodyReach> reach, std::span<const LineSample> samples,
                            std::size_t from, std::span<const GapPair> pairs, GapScratch& scratch, double& bound_mm,
                            std::span<const double> room) {
  const std::size_t n = reach.size(), m = pairs.size();
  // A pair with a fixed body moves by its other body's bound, so its sum is that body's: per
  // body the least allowance of such pairs decides them all, and the loop over samples visits
  // bodies and the pairs of two moving bodies only (a cell of 50 parts has ~400 pairs with a
  // fixed body and a few moving ones).
  scratch.limit.assign(n, INFINITY);
  for (std::size_t k = 0; k < n && k < room.size(); ++k) scratch.limit[k] = room[k];
  scratch.moving.clear();
  for (std::size_t i = 0; i < m; ++i) {
    const GapPair& p = pairs[i];
    if (p.a >= 0 && p.b >= 0) scratch.moving.push_back(static_cast<std::uint32_t>(i));
    else if (const int k = std::max(p.a, p.b); k >= 0)
      scratch.limit[static_cast<std::size_t>(k)] = std::min(scratch.limit[static_cast<std::size_t>(k)], p.allow_mm);
  }
  std::vector<double>& sums = scratch.sums;
  sums.assign(2 * (n + m) + n, 0.0);  // per body then per pair: accepted sums, tentative ones; step
  double* acc = sums.data();
  double* next = sums.data() + n + m;
  double* step = sums.data() + 2 * (n + m);
  bound_mm = 0;
  // The accepted sums at the front of `sums` on return (per pair: its motion bound to j; a
  // pair with a fixed body: its moving body's sum).
  const auto accepted = [&](std::size_t j) {
    if (acc != sums.data()) std::copy(acc, acc + n + m, sums.begin());
    for (std::size_t i = 0; i < m; ++i) {
      const GapPair& p = pairs[i];
      if (p.a < 0 || p.b < 0) sums[n + i] = p.a >= 0 ? sums[static_cast<std::size_t>(p.a)] : p.b >= 0 ? sums[static_cast<std::size_t>(p.b)] : 0.0;
    }
    return j;
  };
  for (std::size_t j = from + 1; j < samples.size(); ++j) {
    const JointVector delta = samples[j].joints - samples[j - 1].joints;
    bool fits = true;
    for (std::size_t k = 0; k < n; ++k) {
      step[k] = robots::max_displacement(reach[k], delta);
      next[k] = acc[k] + step[k];
      fits = fits && next[k] <= kLineSafety * scratch.limit[k];
    }
    for (const std::uint32_t i : scratch.moving) {
      next[n + i] = acc[n + i] + pair_displacement(reach, pairs[i], delta);
      fits = fits && next[n + i] <= kLineSafety * pairs[i].allow_mm;
    }
    if (!fits && j > from + 1) return accepted(j - 1);  // acc and bound_mm: up to j - 1
    std::swap(acc, next);
    bound_mm = n ? *std::max_element(acc, acc + n) : 0.0;
    if (!fits) return accepted(j);  // one interval always goes (plan_line kept it within 0.9 * step_mm)
  }
  return accepted(samples.size() - 1);
}

int joint_move_intervals(std::span<const robots::BodyReach> reach, const JointVector& from, const JointVector& to,
                         double step_mm, std::span<const BodyPair> pairs) {
  const double d = max_body_displacement(reach, to - from, pairs);
  return interval_count(d / step_mm);
}

LineStatus plan_line(const robots::Robot& robot, std::span<const robots::BodyReach> reach, const LineRequest& req,
                     LinePlan& out) {
  out = LinePlan{};
  const LineContext c{robot, reach, req, req.base.inverse(), req.tool.inverse(), kLineSafety * req.step_mm};
  const Location flange0 = c.base_inv * line_pose(req.path, 0) * c.tool_inv;
  if (check_margins(c, flange0, 0, out) != LineStatus::ok) return out.status;
  // Also every step_mm: step_mm scales with the cell, so a cell drawn in metres or km gets
  // the same samples and verdicts as in mm (docs/stiff-cases.md, scale cases).
  const int n = std::max({interval_count(req.path.length / kLineSampleMm),
                          interval_count(req.path.length / req.step_mm),
                          interval_count(req.path.angle_deg() / kLineSampleDeg)});
  out.samples.reserve(static_cast<std::size_t>(std::min(n, 65536)) * 2 + 1);  // n may be 2^30 for a line out of reach
  LineSample prev{0, req.start};
  out.samples.push_back(prev);
  for (int i = 1; i <= n; ++i) {
    LineSample next;
    next.s = static_cast<double>(i) / n;
    if (solve_sample(c, next.s, prev.joints, next.joints, out) != LineStatus::ok) return out.status;
    if (refine(c, prev, next, 0, out) != LineStatus::ok) return out.status;
    prev = next;
  }
  return out.status;
}

}  // namespace asimov::motion
