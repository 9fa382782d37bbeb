// Recorders of a walk (motion/README.md: trace, replay, accuracy and timing).
#include "asimov/motion/recorders.hpp"

#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/world.hpp"

#include <algorithm>
#include <cmath>

namespace asimov::motion {

void TraceRecorder::on_checked_pose(double t, const robots::JointVector& q, bool) {
  if (!on) return;
  if (samples.size() >= max_samples) {
    truncated = true;
    return;
  }
  samples.push_back({t, q, base * robots::flange_pose(robot, q) * tool, {}, Location::Identity()});
  if (world)
    if (auto c = world->carried(q)) samples.back().part = std::move(c->name), samples.back().part_pose = c->pose;
}

void PartHistory::observe(const CellRuntime& runtime) {
  const auto& parts = runtime.clock().parts();
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const PartState& p = parts[i];
    PartSegment s{static_cast<int>(i), p.anchor_s, p.holder, p.conveyor, p.anchor, p.velocity, p.end_s};
    if (p.holder == Holder::carried) s.pose = runtime.grip_of(i), s.velocity.setZero(), s.end_s = std::numeric_limits<double>::infinity();
    if (i < last_.size()) {
      PartSegment& l = segments[last_[i]];
      // The carried part's anchor follows the flange (DeviceClock::move_carried): not a change.
      const bool same = l.holder == s.holder &&
                        (s.holder == Holder::carried ||
                         (l.time_s == s.time_s && l.conveyor == s.conveyor && l.velocity == s.velocity &&
                          l.end_s == s.end_s && l.pose.matrix() == s.pose.matrix()));
      if (same) continue;
      if (s.time_s <= l.time_s) {  // changed again at the same instant: the later state holds
        s.time_s = l.time_s;
        l = s;
        continue;
      }
      last_[i] = segments.size();
    } else {
      last_.resize(i + 1, segments.size());  // fed parts appear in clock order
      last_[i] = segments.size();
    }
    segments.push_back(s);
  }
}

void ReplayRecorder::on_walk_begin(const Trajectory& tr) {
  current = &tr;
  if (grid_s > 0 && runtime) parts.observe(*runtime);
}

void ReplayRecorder::push(double t, const robots::JointVector& q, bool checked) {
  if (!samples.empty() && t <= samples.back().time_s) {
    if (t < samples.back().time_s) return;
    checked = checked || samples.back().checked;  // same instant (a zero-length motion)
    samples.pop_back();
  }
  if (samples.size() >= max_samples) {
    truncated = true;
    return;
  }
  samples.push_back({t, q, current->step, checked, (base * robots::flange_pose(robot, q) * tool).translation()});
}

void ReplayRecorder::on_stretch(const Trajectory& tr, const Stretch& s) {
  if (!(grid_s > 0)) return;
  // The grid instants strictly between two checked poses, joints on the exact path (straight
  // lines: seeded with the last replay joints).
  for (double k = std::floor(s.t_from / grid_s) + 1; k * grid_s < s.t_to; ++k) {
    const double t = k * grid_s;
    push(t,
         s.blended                    ? blended_joints_at(tr, t)
         : tr.kind == PathKind::joint ? joint_path_at(tr, t)
             : line_path_between(robot, tr, s.sample_from, s.sample_to, t, samples.empty() ? nullptr : &samples.back().joints)
                   .joints,
         false);
  }
}

void ReplayRecorder::on_checked_pose(double t, const robots::JointVector& q, bool) {
  if (!(grid_s > 0)) return;
  push(t, q, true);
  if (runtime) parts.observe(*runtime);  // the clock is at t (the world posed the parts there)
}

void ReplayRecorder::on_contact(const CollisionReport& report, const robots::JointVector& q_halt, double) {
  if (!(grid_s > 0)) return;
  // The arm stands at the halting pose from time_free_s on.
  while (!samples.empty() && samples.back().time_s > report.time_free_s) samples.pop_back();
  push(report.time_free_s, q_halt, false);
  if (runtime) parts.observe(*runtime);
}

void AccuracyRecorder::on_stretch(const Trajectory& tr, const Stretch& s) {
  figures.step_displacement_mm = std::max(figures.step_displacement_mm, s.bound_mm);
  if (tr.kind != PathKind::line || s.blended) return;  // the blend leaves the line on purpose
  const LineSample &a = tr.line.samples[s.sample_from], &b = tr.line.samples[s.sample_to];
  const robots::JointVector mid = interpolate_joints(a.joints, b.joints, 0.5);
  figures.line_deviation.merge(
      pose_error(tr.base * robots::flange_pose(robot, mid) * tr.tool, line_pose(tr.path, (a.s + b.s) / 2)));
  ++figures.line_intervals;
}

void AccuracyRecorder::on_ik(const PoseError& residual, std::uint64_t solves) {
  figures.ik_residual.merge(residual);
  figures.ik_solves += solves;
}

void AccuracyRecorder::on_contact(const CollisionReport& report, const robots::JointVector&, double) {
  ++figures.contacts;
  figures.contact_bracket_s = std::max(figures.contact_bracket_s, report.time_s - report.time_free_s);
}

void CountRecorder::on_query(const collision::QueryResult& r, const QueryCost& cost) {
  counts.pairs_enabled += r.counts.pairs_enabled;
  counts.pairs_after_minimax += r.counts.pairs_after_minimax;
  counts.pairs_after_voxels += r.counts.pairs_after_voxels;
  counts.voxel_pairs += r.counts.voxel_pairs;
  counts.face_pairs += r.counts.face_pairs;
  if (cost.kind == QueryKind::bisection_pose) ++bisection;
}

void ClearanceRecorder::on_distance(const collision::BodyPair& pair, const collision::DistanceResult& r,
                                    const DistanceCost& cost) {
  // A cut-off answer (beyond) is only a lower bound: the pair was not that near.
  if (r.status == collision::DistanceStatus::beyond || !(r.distance < within_mm)) return;
  held_.push_back({pair, r.distance, cost.t, cost.step, r.point_a, r.point_b});
}

void ClearanceRecorder::on_contact(const CollisionReport& report, const robots::JointVector&, double) {
  if (clearance_mm <= 0) {
    const collision::BodyPair pair{std::min(report.id_a, report.id_b), std::max(report.id_a, report.id_b)};
    held_.push_back({pair, 0, report.time_s, report.step, report.point, report.point});
  }
  commit(report.time_s);
}

void ClearanceRecorder::commit(double until_s) {
  for (const ClearanceApproach& h : held_) {
    if (h.time_s > until_s) continue;  // after the contact: never reached
    const auto same = [&h](const ClearanceApproach& a) { return a.pair.a == h.pair.a && a.pair.b == h.pair.b; };
    auto it = std::find_if(pairs.begin(), pairs.end(), same);
    if (it == pairs.end()) it = pairs.insert(pairs.end(), h);
    else if (h.distance_mm < it->distance_mm || (h.distance_mm == it->distance_mm && h.time_s < it->time_s))
      *it = h;  // ties: the earliest (a contact's instant)
    else continue;
    it->lower_bound_mm = std::max(0.0, std::min(it->distance_mm - kMinimumToleranceMm, bound_of(it->pair)));
  }
  held_.clear();
}

double ClearanceRecorder::bound_of(const collision::BodyPair& pair) const {
  for (const auto& [p, lower] : bounds_)
    if (p == pair) return lower;
  return std::numeric_limits<double>::infinity();
}

void ClearanceRecorder::on_distance_bound(const collision::BodyPair& pair, double lower_mm) {
  auto b = std::find_if(bounds_.begin(), bounds_.end(), [&](const auto& x) { return x.first == pair; });
  if (b == bounds_.end()) bounds_.emplace_back(pair, lower_mm);
  else b->second = std::min(b->second, lower_mm);
  for (ClearanceApproach& a : pairs)
    if (a.pair == pair) a.lower_bound_mm = std::max(0.0, std::min(a.lower_bound_mm, lower_mm));
}

std::vector<ClearanceApproach> ClearanceRecorder::nearest_first() const {
  std::vector<ClearanceApproach> out = pairs;
  std::stable_sort(out.begin(), out.end(),
                   [](const ClearanceApproach& x, const ClearanceApproach& y) { return x.distance_mm < y.distance_mm; });
  return out;
}

void TimingRecorder::on_walk_begin(const Trajectory&) {
  t0_ = Clock::now();
  k0_ = cpu_ticks();
  query_ticks_ = grid_ticks_ = 0;
  other0_ = timing.collision_s + timing.preprocess_s;
}

void TimingRecorder::on_query(const collision::QueryResult&, const QueryCost& cost) {
  if (cost.kind != QueryKind::checked_pose) return;  // bisection: timed as a whole (on_contact)
  (cost.built_grid ? grid_ticks_ : query_ticks_) += cost.ticks;
}

void TimingRecorder::on_contact(const CollisionReport&, const robots::JointVector&, double search_s) {
  timing.collision_s += search_s;
}

void TimingRecorder::on_walk_end() {
  const double wall = std::chrono::duration<double>(Clock::now() - t0_).count();
  const std::uint64_t k = cpu_ticks() - k0_;
  const double per_tick = k > 0 ? wall / static_cast<double>(k) : 0.0;
  timing.collision_s += static_cast<double>(query_ticks_) * per_tick;
  timing.preprocess_s += static_cast<double>(grid_ticks_) * per_tick;
  timing.motion_s += wall - (timing.collision_s + timing.preprocess_s - other0_);
}

}  // namespace asimov::motion
