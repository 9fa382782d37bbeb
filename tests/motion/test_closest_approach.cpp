// The clearance report's minimum (docs/collision.md §12): per pair, the least distance along the
// motion to within kMinimumToleranceMm, against brute force on the same executed path.
//
// Random runs of two blended motions (MOVE or MOVES, continuous path on) from READY to tool poses
// just above the table and the objects, in the PUMA cell and in a cell of meshed objects. The
// executed path is recorded from the walk's stretches (the joints the walker itself poses: the
// blended overlap, joint moves, straight lines by IK between their samples) and a separate World
// of the same cell measures every pair's exact distance along it. Brute force: N uniform samples
// of the run's time (the long variant, tag [.long]: 10^5); the default variant takes 2,000
// uniform samples and then, around each pair's three nearest, every sample of a 10^5 grid within
// one coarse step (the 10^5-sample minimum wherever the nearest approach is within a coarse step
// of one of the three: smooth approaches). Checked per pair: the reported minimum is never above
// the brute-force one by more than the tolerance, nor below it by more (it is a distance met);
// a pair the report leaves out never came within report_within_mm less the tolerance; the
// report's certified lower bound is never above the brute-force minimum.
#include "asimov/collision/mesh_io.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/motion/walk_observer.hpp"
#include "asimov/motion/world.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"
#include "support/joints.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Cell puma_cell() {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = test::jv({0, -90, 90, 0, 0, 0});
  c.tool = trans(0, 0, 200, 0, 0, 0);
  c.tool_shape = collision::transformed(collision::make_box({50, 80, 140}), collision::Pose(Eigen::Translation3d(0, 0, 130)));
  c.objects.push_back(test::box_object("table", {700, 1200, 40}, {750, 0, -420}));
  c.objects.push_back(test::box_object("box", {160, 160, 200}, {600, 250, -300}));
  return c;
}

// The PUMA with meshed objects: a tessellated sphere and a cylinder on the table, the tool a
// cylinder too (faces at every angle to each other, unlike the boxes').
Cell meshed_cell() {
  Cell c = puma_cell();
  c.tool_shape = collision::transformed(collision::make_cylinder(30, 140, 24), collision::Pose(Eigen::Translation3d(0, 0, 130)));
  c.objects.resize(1);  // the table
  CellObject ball{"ball", collision::make_sphere(90, 0.5).value(), Location::Identity()};
  ball.pose.translation() = collision::Vec3(600, 250, -310);
  CellObject post{"post", collision::make_cylinder(40, 160, 32), Location::Identity()};
  post.pose.translation() = collision::Vec3(550, -250, -320);
  c.objects.push_back(std::move(ball));
  c.objects.push_back(std::move(post));
  return c;
}

// The walk's executed path, from its stretches (as the walker's continuous checking poses it).
struct PathRecorder final : WalkObserver {
  struct Piece {
    std::shared_ptr<const Trajectory> tr;
    Stretch s;
  };
  std::vector<std::shared_ptr<const Trajectory>> walks;
  std::vector<Piece> pieces;
  void on_walk_begin(const Trajectory& tr) override { walks.push_back(std::make_shared<const Trajectory>(tr)); }
  void on_stretch(const Trajectory&, const Stretch& s) override { pieces.push_back({walks.back(), s}); }
};

JointVector joints_at(const robots::Robot& robot, const PathRecorder::Piece& p, double t, const JointVector& seed) {
  const Trajectory& tr = *p.tr;
  if (p.s.blended) return blended_joints_at(tr, t);
  if (tr.kind != PathKind::line) return joint_path_at(tr, t);
  return line_path_between(robot, tr, p.s.sample_from, p.s.sample_to, t, &seed).joints;
}

struct Outcome {
  int runs = 0, motions = 0, contacts = 0, reported = 0, absent_checked = 0, uncertified = 0;
  double worst_above = 0, worst_below = 0;  // reported - brute force, the largest each way
};

// One run and its check. `dense`: the default variant's refinement around the coarse minima.
void run_case(const Cell& cell, std::mt19937& rng, int samples, bool dense, Outcome& out) {
  Simulator sim(cell);
  PathRecorder path;
  sim.add_observer(path);
  sim.settings().continuous_path = true;
  std::uniform_real_distribution<double> u(0, 1);
  // Tool points over the table and the objects, 0-60 mm above their tops, tool pointing down.
  const auto target = [&] {
    const double x = 420 + 360 * u(rng), y = -380 + 760 * u(rng);
    const double top = (x > 500 && x < 700 && y > 150 && y < 350) ? -200 : -400;
    return trans(x, y, top + 60 * u(rng), 180 * u(rng) - 90, 180, 0);
  };
  int planned = 0;
  MotionResult r;
  for (int k = 0; k < 2; ++k) {
    r = sim.start_move(target(), u(rng) < 0.5, {}, k + 1);
    if (r.status == MotionStatus::collision) break;
    if (r.status == MotionStatus::ok) ++planned;
  }
  if (r.status == MotionStatus::ok) r = sim.finish_motion();
  if (planned == 0) return;
  ++out.runs;
  out.motions += planned;
  out.contacts += r.status == MotionStatus::collision;
  const double t_end = sim.time_s();
  // The run's executed path over [0, t_end] (a contact ends it at the contact instant).
  std::vector<PathRecorder::Piece> pieces;
  for (const auto& p : path.pieces)
    if (p.s.t_to > p.s.t_from) pieces.push_back(p);
  if (pieces.empty()) return;  // a contact at the first pose: no path
  World world(cell);
  collision::Engine& engine = *world.engine();
  const std::vector<collision::BodyPair> pairs(world.pairs().begin(), world.pairs().end());
  const double within = cell.collision.report_within_mm;
  // Distances of every pair at time t (exact below the cut-off, else a lower bound >= it).
  std::size_t piece = 0;
  JointVector seed = cell.start_joints;
  // Distances at time t of every pair (only = npos) or of one (the others left as they were).
  const auto measure = [&](double t, std::vector<double>& d, std::size_t only = std::string::npos) {
    while (piece + 1 < pieces.size() && t > pieces[piece].s.t_to) ++piece;
    while (piece > 0 && t < pieces[piece].s.t_from) --piece;
    const JointVector q = joints_at(cell.robot, pieces[piece], t, seed);
    seed = q;
    world.pose(q, t);
    d.resize(pairs.size(), kInf);
    for (std::size_t i = 0; i < pairs.size(); ++i)
      if (only == std::string::npos || i == only)
        d[i] = engine.distance(pairs[i].a, pairs[i].b, {.upper_mm = within + 1}).distance;
  };
  const double t0 = pieces.front().s.t_from, span = t_end - t0;
  std::vector<double> best(pairs.size(), kInf), best_t(pairs.size(), 0), d;
  std::vector<std::vector<std::pair<double, double>>> nearest(pairs.size());  // (distance, sample index)
  for (int k = 0; k <= samples; ++k) {
    measure(t0 + span * k / samples, d);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (d[i] < best[i]) best[i] = d[i], best_t[i] = t0 + span * k / samples;
      if (dense && d[i] < within + 1) {
        auto& n = nearest[i];
        n.emplace_back(d[i], k);
        std::sort(n.begin(), n.end());
        if (n.size() > 3) n.pop_back();
      }
    }
  }
  if (dense) {  // every sample of the 10^5 grid within one coarse step of the three nearest
    constexpr int kFine = 100000;
    const int ratio = kFine / samples;
    for (std::size_t i = 0; i < pairs.size(); ++i)
      for (const auto& [dist, k] : nearest[i])
        for (int f = static_cast<int>(k) * ratio - ratio; f <= static_cast<int>(k) * ratio + ratio; ++f) {
          if (f < 0 || f > kFine) continue;
          measure(t0 + span * f / kFine, d, i);
          if (d[i] < best[i]) best[i] = d[i], best_t[i] = t0 + span * f / kFine;
        }
  }
  const auto approaches = sim.recorders().clearance.pairs;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const auto it = std::find_if(approaches.begin(), approaches.end(), [&](const ClearanceApproach& a) { return a.pair == pairs[i]; });
    INFO("pair " << sim.body_name(pairs[i].a) << " / " << sim.body_name(pairs[i].b) << ", brute force " << best[i]
                  << " at t = " << best_t[i] << " of [" << t0 << ", " << t_end << "]; run " << out.runs << ", "
                  << (r.status == MotionStatus::collision ? "contact" : "no contact"));
    if (it == approaches.end()) {
      CHECK(best[i] >= within - kMinimumToleranceMm);
      ++out.absent_checked;
      continue;
    }
    INFO("reported " << it->distance_mm << " at t = " << it->time_s << ", lower bound " << it->lower_bound_mm);
    if (it->distance_mm == 0) {
      // The contact: 0 at the contact instant by definition (the walker's bracket of 1e-6 s; the
      // samples pose the path as the walker does, up to the IK seeds of straight lines).
      CHECK(r.status == MotionStatus::collision);
      CHECK(best[i] <= 0.01);
      continue;
    }
    ++out.reported;
    CHECK(it->distance_mm <= best[i] + kMinimumToleranceMm);
    CHECK(it->distance_mm >= best[i] - kMinimumToleranceMm);
    CHECK(it->lower_bound_mm <= best[i] + 1e-9);
    out.uncertified += it->lower_bound_mm < it->distance_mm - kMinimumToleranceMm - 1e-12;
    out.worst_above = std::max(out.worst_above, it->distance_mm - best[i]);
    out.worst_below = std::max(out.worst_below, best[i] - it->distance_mm);
  }
}

void run_cases(const Cell& cell, int motions, int samples, bool dense, unsigned seed) {
  std::mt19937 rng(seed);
  Outcome out;
  const auto start = std::chrono::steady_clock::now();
  while (out.motions < motions) run_case(cell, rng, samples, dense, out);
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - start;
  WARN(wall.count() << " s: " << out.runs << " runs, " << out.motions << " motions (" << out.contacts << " ending in contact): " << out.reported
                << " reported pairs, reported - brute force within [" << -out.worst_below << ", " << out.worst_above
                << "] mm, " << out.uncertified << " not certified to the tolerance; " << out.absent_checked
                << " pairs left out checked");
  CHECK(out.reported > motions / 10);  // the approaches are near enough to be reported
}

}  // namespace

TEST_CASE("closest approach: the reported minimum is the brute-force minimum to 1e-3 mm (PUMA cell)", "[closest]") {
  run_cases(puma_cell(), 1000, 2000, true, 11);
}

TEST_CASE("closest approach: the reported minimum is the brute-force minimum to 1e-3 mm (meshed cell)", "[closest]") {
  run_cases(meshed_cell(), 1000, 2000, true, 12);
}

TEST_CASE("closest approach: 10^5 uniform samples per run (long)", "[.long][closest]") {
  run_cases(puma_cell(), 1000, 100000, false, 21);
  run_cases(meshed_cell(), 1000, 100000, false, 22);
}
