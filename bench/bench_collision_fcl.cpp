// The four-step engine against FCL 0.7 (BVHModel<OBBRSS>) on the same meshes and poses, in one
// run: (a) Coal's env/rob method (2,000 vs 200 faces, 10,000 random poses), (b) pairs of 50 to
// 50,000 faces, (c) the PUMA default cell along a recorded trajectory (FCL: DynamicAABBTree
// broadphase). Prints median / p95 / mean us per query, ratio ours/FCL (of medians; of means too) and
// agreement, classifies every disagreement (touching, containment, other) and writes
// bench/results/collision_fcl.json. Run: bench_collision_fcl [--quick] [--out FILE].
#include "bench/fcl_mesh.hpp"
#include "bench/scenes.hpp"
#include "collision/src/distance_tree.hpp"
#include "collision/src/voxel_grid.hpp"
#include "asimov/collision/engine.hpp"
#include "asimov/collision/distance.hpp"
#include "asimov/robots/robot.hpp"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <malloc.h>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

using namespace asimov;
using collision::BodyId;
using collision::Engine;
using collision::Polyhedron;
using collision::Pose;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kTouchMm = 1e-6;  // "touching": distance within 1e-6 mm of zero

struct Stats {
  double median = 0, p95 = 0, mean = 0;
};
Stats stats(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  Stats s;
  s.median = t[t.size() / 2];
  s.p95 = t[std::min(t.size() - 1, t.size() * 95 / 100)];
  s.mean = std::accumulate(t.begin(), t.end(), 0.0) / static_cast<double>(t.size());
  return s;
}
double raw_us_since(Clock::time_point t0) { return std::chrono::duration<double, std::micro>(Clock::now() - t0).count(); }
// The cost of reading the clock twice, measured once at start-up (median of 10,001 empty
// timings) and subtracted from every per-query time, so sub-microsecond queries compare fairly.
double timer_overhead_us = 0;
double us_since(Clock::time_point t0) { return std::max(0.0, raw_us_since(t0) - timer_overhead_us); }
void measure_timer_overhead() {
  std::vector<double> t(10001);
  for (double& x : t) {
    const auto s = Clock::now();
    x = raw_us_since(s);
  }
  std::nth_element(t.begin(), t.begin() + 5000, t.end());
  timer_overhead_us = t[5000];
}

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const Polyhedron& m) { return bench::fcl_mesh<fcl::OBBRSSd>(m); }

struct Row;
void profile(const std::vector<collision::QueryResult>& results, const std::vector<double>& t,
             const std::vector<double>& peer, Row& row);

struct Disagreements {
  int touching = 0, containment = 0, other = 0;
  int total() const { return touching + containment + other; }
};

struct Row {
  std::string name;
  std::size_t queries = 0;
  std::string m{};  // halvings chosen per body
  double voxel_pairs = 0, face_pairs = 0, after_minimax = 0;  // means per query (ours)
  // Filter profile (docs/collision-method.md §8): where each of our queries ended, with its median time.
  std::array<std::size_t, 4> ended{};      // step 2, step 3, step 4 free, contact
  std::array<double, 4> ended_median_us{};
  std::array<double, 4> ended_share_us{};  // each class's part of the mean (sum = ours.mean)
  std::array<double, 4> peer_share_us{};   // FCL's time on the same poses, by our class (sum = peer.mean)
  Stats ours{}, peer{};
  double ours_prep_ms = 0, peer_prep_ms = 0;
  double ours_colliding = 0, peer_colliding = 0;
  Disagreements dis{};
  double ratio() const { return ours.median / peer.median; }
  double mean_ratio() const { return ours.mean / peer.mean; }  // the tail: interlocked poses, late contacts
  double agreement() const { return 1.0 - static_cast<double>(dis.total()) / static_cast<double>(queries); }
};

void profile(const std::vector<collision::QueryResult>& results, const std::vector<double>& t,
             const std::vector<double>& peer, Row& row) {
  std::array<std::vector<double>, 4> by;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    const int k = r.collided ? 3 : r.counts.pairs_after_minimax == 0 ? 0 : r.counts.pairs_after_voxels == 0 ? 1 : 2;
    by[static_cast<std::size_t>(k)].push_back(t[i]);
    row.peer_share_us[static_cast<std::size_t>(k)] += peer[i] / static_cast<double>(results.size());
  }
  for (std::size_t k = 0; k < 4; ++k) {
    row.ended[k] = by[k].size();
    row.ended_median_us[k] = by[k].empty() ? 0 : stats(by[k]).median;
    row.ended_share_us[k] = std::accumulate(by[k].begin(), by[k].end(), 0.0) / static_cast<double>(results.size());
  }
}

// Why ours and FCL differ on one pair at one pose. Ours is the exact answer (checked against
// brute force here); FCL misses containment and decides touching with its own rounding.
void classify(bool ours, const collision::QueryResult& r, const Polyhedron& ma, const Pose& pa, const Polyhedron& mb,
              const Pose& pb, fcl::CollisionObjectd& oa, fcl::CollisionObjectd& ob, Disagreements& d) {
  if (ours != collision::brute_force_collides(ma, pa, mb, pb)) {
    std::fprintf(stderr, "BUG: four steps differ from brute force\n");
    ++d.other;
    return;
  }
  if (ours && r.contact.kind == collision::ContactKind::containment) {
    ++d.containment;
    return;
  }
  if (ours) {  // faces meet exactly; FCL says free: touching if FCL's distance is ~0
    fcl::DistanceRequestd req;
    fcl::DistanceResultd res;
    fcl::distance(&oa, &ob, req, res);
    if (res.min_distance <= kTouchMm) ++d.touching; else ++d.other;
    return;
  }
  // FCL says contact, exact test says free: touching if the exact distance is ~0.
  if (collision::brute_force_collides(ma, pa, mb, pb, kTouchMm)) ++d.touching; else ++d.other;
}

// One moving mesh against a fixed one over `poses` (ours: Engine with a static body).
Row pair_row(const std::string& name, const Polyhedron& fixed, const Polyhedron& moving, const std::vector<Pose>& poses) {
  Row row{.name = name, .queries = poses.size()};
  auto t0 = Clock::now();
  Engine e;
  const BodyId a = e.add_body({.name = "fixed", .mesh = fixed, .is_static = true, .halvings = collision::kAutoHalvings});
  const BodyId b = e.add_body({.name = "moving", .mesh = moving, .halvings = collision::kAutoHalvings});
  row.m = "M " + std::to_string(e.body_halvings(a)) + "/" + std::to_string(e.body_halvings(b));
  e.set_pose(a, Pose::Identity());
  e.set_pose(b, poses[0]);
  (void)e.check();  // builds the grids (lazy)
  row.ours_prep_ms = us_since(t0) / 1e3;

  t0 = Clock::now();
  fcl::CollisionObjectd fa(fcl_model(fixed), Pose::Identity());
  fcl::CollisionObjectd fb(fcl_model(moving), Pose::Identity());
  row.peer_prep_ms = us_since(t0) / 1e3;

  std::vector<double> tours(poses.size()), tpeer(poses.size());
  std::vector<char> ours(poses.size()), peer(poses.size());
  std::vector<collision::QueryResult> results(poses.size());
  for (int pass = 0; pass < 2; ++pass) {  // pass 0 warms caches, pass 1 is timed
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const auto s = Clock::now();
      e.set_pose(b, poses[i]);
      results[i] = e.check();
      tours[i] = us_since(s);
      ours[i] = results[i].collided;
    }
    fcl::CollisionRequestd req;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const auto s = Clock::now();
      fb.setTransform(poses[i]);
      fcl::CollisionResultd res;
      fcl::collide(&fa, &fb, req, res);
      tpeer[i] = us_since(s);
      peer[i] = res.isCollision();
    }
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    row.voxel_pairs += static_cast<double>(results[i].counts.voxel_pairs) / static_cast<double>(poses.size());
    row.face_pairs += static_cast<double>(results[i].counts.face_pairs) / static_cast<double>(poses.size());
    row.after_minimax += static_cast<double>(results[i].counts.pairs_after_minimax) / static_cast<double>(poses.size());
    row.ours_colliding += ours[i];
    row.peer_colliding += peer[i];
    if (ours[i] != peer[i]) {
      fb.setTransform(poses[i]);
      classify(ours[i], results[i], fixed, Pose::Identity(), moving, poses[i], fa, fb, row.dis);
    }
  }
  row.ours_colliding /= static_cast<double>(poses.size());
  row.peer_colliding /= static_cast<double>(poses.size());
  row.ours = stats(tours);
  row.peer = stats(tpeer);
  profile(results, tours, tpeer, row);
  return row;
}

// (c) The PUMA default cell: links, tool and cell objects, adjacent pairs disabled as in
// motion/world.cpp; FCL gets the same bodies in a DynamicAABBTree manager and a callback
// that skips disabled pairs and stops at the first contact.
struct FclScene {
  Engine* engine = nullptr;
  std::vector<fcl::CollisionObjectd*> objects{};
  bool hit = false;
  BodyId a = 0, b = 0;
};
bool fcl_callback(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
  auto* s = static_cast<FclScene*>(data);
  const auto i = static_cast<BodyId>(reinterpret_cast<std::uintptr_t>(o1->getUserData()));
  const auto j = static_cast<BodyId>(reinterpret_cast<std::uintptr_t>(o2->getUserData()));
  if (i == j || !s->engine->pair_enabled(i, j)) return false;
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  fcl::collide(o1, o2, req, res);
  if (!res.isCollision()) return false;
  s->hit = true;
  s->a = std::min(i, j);
  s->b = std::max(i, j);
  return true;
}

Row puma_row(const std::string& name, int moves, int samples) {
  const bench::PumaScene scene = bench::make_puma_scene(moves, samples);
  const motion::Cell& cell = scene.cell;
  const auto& robot = cell.robot;
  Row row{.name = name, .queries = scene.trajectory.size()};

  // Bodies: robot links, tool, objects. link[k] = DH frame of body k, -1 for static.
  std::vector<Polyhedron> meshes;
  std::vector<int> link;
  std::vector<std::string> names;
  for (const auto& b : robot.bodies) {
    meshes.push_back(b.mesh);
    link.push_back(b.link);
    names.push_back(b.name);
  }
  if (cell.tool_shape) {
    meshes.push_back(*cell.tool_shape);
    link.push_back(robot.joint_count());
    names.push_back("tool");
  }
  for (const auto& o : cell.objects) {
    meshes.push_back(o.mesh);
    link.push_back(-1);
    names.push_back(o.name);
  }
  const std::size_t n = meshes.size();
  std::vector<std::vector<Pose>> poses(scene.trajectory.size(), std::vector<Pose>(n));
  std::vector<Pose> frames;
  for (std::size_t t = 0; t < scene.trajectory.size(); ++t) {
    robots::link_frames(robot, scene.trajectory[t], frames);
    std::size_t obj = 0;
    for (std::size_t k = 0; k < n; ++k)
      poses[t][k] = link[k] > 0 ? cell.base * frames[static_cast<std::size_t>(link[k])]
                    : link[k] == 0 ? cell.base
                                   : cell.objects[obj++].pose;
  }

  auto t0 = Clock::now();
  Engine e;
  constexpr int kStatic = 1000;
  for (std::size_t k = 0; k < n; ++k) {
    const bool fixed = link[k] <= 0;
    const int group = fixed ? kStatic : std::min(link[k], robot.joint_count());
    e.add_body({.name = names[k], .mesh = meshes[k], .group = group, .is_static = fixed,
                .halvings = collision::kAutoHalvings});
    row.m += (k ? "," : "M ") + std::to_string(e.body_halvings(static_cast<BodyId>(k)));
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (link[i] >= 0 && link[j] >= 0 && std::abs(std::min(link[i], 6) - std::min(link[j], 6)) <= 1)
        e.set_pair_enabled(static_cast<BodyId>(i), static_cast<BodyId>(j), false);
  // The tool is next to link5 and link6 (as in the simulator).
  for (std::size_t k = 0; k < n; ++k) e.set_pose(static_cast<BodyId>(k), poses[0][k]);
  (void)e.check();
  row.ours_prep_ms = us_since(t0) / 1e3;

  t0 = Clock::now();
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objs;
  FclScene fs{.engine = &e};
  fcl::DynamicAABBTreeCollisionManagerd manager;
  for (std::size_t k = 0; k < n; ++k) {
    objs.push_back(std::make_unique<fcl::CollisionObjectd>(fcl_model(meshes[k]), poses[0][k]));
    objs.back()->setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(k)));
    objs.back()->computeAABB();
    manager.registerObject(objs.back().get());
  }
  manager.setup();
  row.peer_prep_ms = us_since(t0) / 1e3;

  const std::size_t q = scene.trajectory.size();
  std::vector<double> tours(q), tpeer(q);
  std::vector<char> ours(q), peer(q);
  std::vector<collision::QueryResult> results(q);
  std::vector<std::pair<BodyId, BodyId>> peer_pair(q);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t t = 0; t < q; ++t) {
      const auto s = Clock::now();
      for (std::size_t k = 0; k < n; ++k)
        if (link[k] > 0) e.set_pose(static_cast<BodyId>(k), poses[t][k]);
      results[t] = e.check();
      tours[t] = us_since(s);
      ours[t] = results[t].collided;
    }
    for (std::size_t t = 0; t < q; ++t) {
      const auto s = Clock::now();
      for (std::size_t k = 0; k < n; ++k)
        if (link[k] > 0) {
          objs[k]->setTransform(poses[t][k]);
          objs[k]->computeAABB();
        }
      manager.update();
      fs.hit = false;
      manager.collide(&fs, fcl_callback);
      tpeer[t] = us_since(s);
      peer[t] = fs.hit;
      peer_pair[t] = {fs.a, fs.b};
    }
  }
  for (std::size_t t = 0; t < q; ++t) {
    row.voxel_pairs += static_cast<double>(results[t].counts.voxel_pairs) / static_cast<double>(q);
    row.face_pairs += static_cast<double>(results[t].counts.face_pairs) / static_cast<double>(q);
    row.after_minimax += static_cast<double>(results[t].counts.pairs_after_minimax) / static_cast<double>(q);
    row.ours_colliding += ours[t];
    row.peer_colliding += peer[t];
    if (ours[t] == peer[t]) continue;
    const auto [a, b] = ours[t] ? std::pair{results[t].contact.body_a, results[t].contact.body_b} : peer_pair[t];
    objs[a]->setTransform(poses[t][a]);
    objs[b]->setTransform(poses[t][b]);
    std::printf("  pose %zu: ours %d fcl %d on %s / %s\n", t, ours[t], peer[t], names[a].c_str(), names[b].c_str());
    classify(ours[t], results[t], meshes[a], poses[t][a], meshes[b], poses[t][b], *objs[a], *objs[b], row.dis);
  }
  row.ours_colliding /= static_cast<double>(q);
  row.peer_colliding /= static_cast<double>(q);
  row.ours = stats(tours);
  row.peer = stats(tpeer);
  profile(results, tours, tpeer, row);
  return row;
}

void print(const Row& r) {
  std::printf("%-48s %6zu  ours %8.2f %8.2f %8.2f  fcl %8.2f %8.2f %8.2f  ratio %5.2f (mean %4.2f)  coll %4.1f%%/%4.1f%%  "
              "agree %.5f (touch %d, contain %d, other %d)  prep %.1f/%.1f ms  %s  minimax %.2f vp %.0f fp %.0f\n",
              r.name.c_str(), r.queries, r.ours.median, r.ours.p95, r.ours.mean, r.peer.median, r.peer.p95,
              r.peer.mean, r.ratio(), r.mean_ratio(), 100 * r.ours_colliding, 100 * r.peer_colliding, r.agreement(), r.dis.touching,
              r.dis.containment, r.dis.other, r.ours_prep_ms, r.peer_prep_ms, r.m.c_str(), r.after_minimax, r.voxel_pairs, r.face_pairs);
  std::printf("    ours ended at: step 2 %zu (median %.2f us), step 3 %zu (%.2f us), step 4 free %zu (%.2f us), "
              "contact %zu (%.2f us); share of the mean %.2f / %.2f / %.2f / %.2f us (fcl on the same poses "
              "%.2f / %.2f / %.2f / %.2f us)\n",
              r.ended[0], r.ended_median_us[0], r.ended[1], r.ended_median_us[1], r.ended[2], r.ended_median_us[2],
              r.ended[3], r.ended_median_us[3], r.ended_share_us[0], r.ended_share_us[1], r.ended_share_us[2],
              r.ended_share_us[3], r.peer_share_us[0], r.peer_share_us[1], r.peer_share_us[2], r.peer_share_us[3]);
  std::fflush(stdout);
}

// Distance (docs/collision.md §11): ours Engine::distance without cut-off against FCL's
// fcl::distance (nearest points on, as ours gives witnesses), same meshes and poses. Agreement:
// both in contact (FCL: distance <= 0 or within kTouchMm, ours: status contact), or the distances
// within 1e-6 relative; ours in contact by containment while FCL measures the surfaces is counted
// apart (FCL has no inside).
struct DistanceRow {
  std::string name;
  std::size_t queries = 0;
  Stats ours{}, peer{};
  int contact = 0, agree = 0, containment = 0, other = 0;
  double max_rel = 0;  // largest relative difference of the distances where both measured one
  double face_pairs = 0;  // ours: mean face pairs measured per query
  double node_pairs = 0;  // ours: mean box pairs of the distance trees bounded per query
  double ratio() const { return ours.median / peer.median; }
  double mean_ratio() const { return ours.mean / peer.mean; }
};

DistanceRow distance_row(const std::string& name, const Polyhedron& fixed, const Polyhedron& moving,
                         const std::vector<Pose>& poses) {
  DistanceRow row{.name = name, .queries = poses.size()};
  Engine e;
  const BodyId a = e.add_body({.name = "fixed", .mesh = fixed, .is_static = true, .halvings = collision::kAutoHalvings});
  const BodyId b = e.add_body({.name = "moving", .mesh = moving, .halvings = collision::kAutoHalvings});
  e.set_pose(a, Pose::Identity());
  e.set_pose(b, poses[0]);
  (void)e.distance(a, b);
  fcl::CollisionObjectd fa(fcl_model(fixed), Pose::Identity());
  fcl::CollisionObjectd fb(fcl_model(moving), Pose::Identity());
  std::vector<double> tours(poses.size()), tpeer(poses.size());
  std::vector<collision::DistanceResult> ours(poses.size());
  std::vector<double> peer(poses.size());
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const auto s = Clock::now();
      e.set_pose(b, poses[i]);
      ours[i] = e.distance(a, b);
      tours[i] = us_since(s);
    }
    fcl::DistanceRequestd req;
    req.enable_nearest_points = true;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const auto s = Clock::now();
      fb.setTransform(poses[i]);
      fcl::DistanceResultd res;
      fcl::distance(&fa, &fb, req, res);
      tpeer[i] = us_since(s);
      peer[i] = res.min_distance;
    }
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const bool oc = ours[i].status == collision::DistanceStatus::contact;
    row.contact += oc;
    row.face_pairs += static_cast<double>(ours[i].face_pairs) / static_cast<double>(poses.size());
    row.node_pairs += static_cast<double>(ours[i].node_pairs) / static_cast<double>(poses.size());
    if (oc && peer[i] <= kTouchMm) {
      ++row.agree;
    } else if (!oc) {
      const double rel = std::fabs(ours[i].distance - peer[i]) / std::max(1.0, peer[i]);
      row.max_rel = std::max(row.max_rel, rel);
      if (rel <= 1e-6) ++row.agree; else ++row.other;
    } else if (ours[i].kind == collision::ContactKind::containment) {
      ++row.containment;
    } else {
      ++row.other;
    }
  }
  row.ours = stats(tours);
  row.peer = stats(tpeer);
  return row;
}

void print(const DistanceRow& r) {
  std::printf("%-48s %6zu  ours %8.2f %8.2f %8.2f  fcl %8.2f %8.2f %8.2f  ratio %5.2f (mean %4.2f)  contact %d  "
              "agree %d (containment %d, other %d, max rel diff %.1e)  face pairs %.1f  node pairs %.0f\n",
              r.name.c_str(), r.queries, r.ours.median, r.ours.p95, r.ours.mean, r.peer.median, r.peer.p95, r.peer.mean,
              r.ratio(), r.mean_ratio(), r.contact, r.agree, r.containment, r.other, r.max_rel, r.face_pairs, r.node_pairs);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string only;  // --only SUBSTRING: run the matching cases only (profiling)
  bool merge = false;
  std::string out = std::string(ASIMOV_SOURCE_DIR) + "/bench/results/collision_fcl.json";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--merge")) merge = true;  // with --only: rows merged into --out
  }
  measure_timer_overhead();
  std::printf("timer overhead %.3f us per query, subtracted\n", timer_overhead_us);
  auto wanted = [&](const std::string& name) { return only.empty() || name.find(only) != std::string::npos; };
  std::printf("%-48s %6s  %-30s %-30s\n", "case", "poses", "ours us: median p95 mean", "fcl us: median p95 mean");
  std::vector<Row> rows;
  const std::size_t n_a = quick ? 1000 : 10000;
  if (wanted("(a)")) {
    rows.push_back(pair_row("(a) env 2000 faces / rob 200 faces", bench::make_env_mesh(), bench::make_rob_mesh(),
                            bench::random_poses(n_a, 1500, 2180)));
    print(rows.back());
  }
  for (const int faces : {50, 200, 1000, 5000, 20000, 50000}) {
    const std::size_t n = quick ? 500 : (faces >= 20000 ? 2000 : 10000);
    const Polyhedron m = bench::make_torus_with_faces(faces, 100);
    if (!wanted("(b) " + std::to_string(m.triangles.size()) + " ")) continue;
    rows.push_back(pair_row("(b) " + std::to_string(m.triangles.size()) + " / " + std::to_string(m.triangles.size()) +
                                " faces",
                            m, m, bench::random_poses(n, 250, 1000 + static_cast<std::uint64_t>(faces))));
    print(rows.back());
  }
  if (wanted("puma")) {
    rows.push_back(puma_row("(c) puma default cell, trajectory", quick ? 4 : 20, 500));
    print(rows.back());
    rows.push_back(puma_row("(c) puma default cell, random configurations", quick ? 2000 : 10000, 1));
    print(rows.back());
  }

  std::vector<DistanceRow> drows;
  if (wanted("distance")) {
    const std::size_t nd = quick ? 500 : 5000;
    drows.push_back(distance_row("distance (a) env 2000 faces / rob 200 faces", bench::make_env_mesh(),
                                 bench::make_rob_mesh(), bench::random_poses(nd, 1500, 2180)));
    print(drows.back());
    for (const int faces : {200, 1000, 5000, 20000}) {
      const Polyhedron m = bench::make_torus_with_faces(faces, 100);
      drows.push_back(distance_row("distance (b) " + std::to_string(m.triangles.size()) + " / " +
                                       std::to_string(m.triangles.size()) + " faces",
                                   m, m, bench::random_poses(faces >= 20000 ? nd / 5 : nd, 250, 1000 + static_cast<std::uint64_t>(faces))));
      print(drows.back());
    }
  }

  // Big meshes (docs/collision.md §13): preprocessing of one 1,000,000-face body (container,
  // closedness, voxel grid at the cost model's M, shells) against FCL's BVHModel<OBBRSS> build of
  // the same mesh, wall time (best of 3), and the memory each keeps: ours the mesh and the grid
  // counted by their vectors, FCL's the growth of resident memory over its build. The
  // 10,000,000-face row (--only "big 10M", about a minute): ours best of 3, FCL's build once
  // (it holds some 6 GB there).
  struct BigRow {
    std::size_t faces = 0;
    double ours_ms = 0, peer_ms = 0;
    double tree_ms = 0, tree_bytes_per_face = 0;  // ours: the distance tree (built on the body's first distance query)
    int m = 0;
    double ours_bytes_per_face = 0, peer_bytes_per_face = 0;
  };
  std::vector<BigRow> big;
  const auto resident_bytes = [] {
    std::ifstream statm("/proc/self/statm");
    std::size_t size = 0, resident = 0;
    statm >> size >> resident;
    return static_cast<double>(resident) * 4096.0;
  };
  for (const int target : {1000000, 10000000}) {
    const bool ten = target == 10000000;
    if (!wanted(ten ? "big 10M" : "big 1M") || (quick && ten)) continue;
    const Polyhedron m = bench::make_torus_with_faces(quick ? 100000 : target, 1000);
    BigRow row{.faces = m.triangles.size()};
    row.ours_ms = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      auto t0 = Clock::now();
      {
        Engine e;
        const BodyId a = e.add_body({.name = "big", .mesh = m, .is_static = true, .halvings = collision::kAutoHalvings});
        const BodyId b = e.add_body({.name = "probe", .mesh = collision::make_box({10, 10, 10})});
        e.set_pose(a, Pose::Identity());
        Pose p = Pose::Identity();
        p.translation() = collision::Vec3(1000, 0, 0);  // on the tube: step 3 builds the grid
        e.set_pose(b, p);
        (void)e.check();
        row.m = e.body_halvings(a);
        row.ours_ms = std::min(row.ours_ms, us_since(t0) / 1e3);
      }
      if (!ten || rep == 0) {
        if (rep == 0) row.peer_ms = 1e300;
        malloc_trim(0);  // our engine's freed memory back to the system first: FCL's growth is its own
        const double before = resident_bytes();
        t0 = Clock::now();
        const auto model = fcl_model(m);
        row.peer_ms = std::min(row.peer_ms, us_since(t0) / 1e3);
        if (rep == 0) row.peer_bytes_per_face = (resident_bytes() - before) / static_cast<double>(row.faces);
      }
    }
    // The distance tree (FCL's BVH is what its distance query descends, so this is the like for
    // like of the distance query; ours is built lazily, on the body's first distance query).
    row.tree_ms = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = Clock::now();
      const collision::DistanceTree tree = collision::build_distance_tree(m);
      row.tree_ms = std::min(row.tree_ms, us_since(t0) / 1e3);
      row.tree_bytes_per_face = static_cast<double>(tree.bytes()) / static_cast<double>(row.faces);
    }
    {
      const collision::VoxelGrid g = collision::build_voxel_grid(m, row.m);
      const std::size_t mesh_bytes = sizeof(collision::Vec3) * m.vertices.size() + sizeof(collision::Triangle) * m.triangles.size();
      const std::size_t grid = sizeof(std::uint32_t) * (g.offsets.size() + g.faces.size() + g.occupied.size()) +
                               sizeof(collision::FloatBox) * g.face_parts.size() + sizeof(collision::Box) * g.content.size() +
                               sizeof(collision::TreeNode) * g.tree.size() + sizeof(collision::TreeSlabs) * g.slabs.size() + g.classes.size();
      row.ours_bytes_per_face = static_cast<double>(mesh_bytes + grid) / static_cast<double>(row.faces);
    }
    std::printf("%-48s %8zu faces  ours %8.1f ms (M %d, %.0f B/face)  fcl BVH build %8.1f ms (%.0f B/face)  ratio %.2f"
                "  distance tree %8.1f ms (%.0f B/face)\n",
                "big mesh preprocessing", row.faces, row.ours_ms, row.m, row.ours_bytes_per_face, row.peer_ms,
                row.peer_bytes_per_face, row.ours_ms / row.peer_ms, row.tree_ms, row.tree_bytes_per_face);
    std::fflush(stdout);
    big.push_back(row);
  }

  nlohmann::json j = nlohmann::json::array();
  for (const Row& r : rows)
    j.push_back({{"name", r.name}, {"ours_us", r.ours.median}, {"peer", "fcl"}, {"peer_us", r.peer.median},
                 {"ratio", r.ratio()}, {"agreement", r.agreement()}, {"ours_p95_us", r.ours.p95},
                 {"ours_mean_us", r.ours.mean}, {"peer_p95_us", r.peer.p95}, {"peer_mean_us", r.peer.mean},
                 {"mean_ratio", r.mean_ratio()},
                 {"queries", r.queries}, {"colliding", r.ours_colliding}, {"peer_colliding", r.peer_colliding},
                 {"disagree_touching", r.dis.touching}, {"disagree_containment", r.dis.containment},
                 {"disagree_other", r.dis.other}, {"halvings", r.m}, {"mean_voxel_pairs", r.voxel_pairs}, {"mean_face_pairs", r.face_pairs},
                 {"mean_pairs_after_minimax", r.after_minimax},
                 {"ended_step2", r.ended[0]}, {"ended_step3", r.ended[1]}, {"ended_step4_free", r.ended[2]},
                 {"ended_contact", r.ended[3]}, {"ended_step2_median_us", r.ended_median_us[0]},
                 {"ended_step3_median_us", r.ended_median_us[1]}, {"ended_step4_free_median_us", r.ended_median_us[2]},
                 {"ended_contact_median_us", r.ended_median_us[3]},
                 {"ended_step2_mean_share_us", r.ended_share_us[0]}, {"ended_step3_mean_share_us", r.ended_share_us[1]},
                 {"ended_step4_free_mean_share_us", r.ended_share_us[2]}, {"ended_contact_mean_share_us", r.ended_share_us[3]},
                 {"peer_step2_mean_share_us", r.peer_share_us[0]}, {"peer_step3_mean_share_us", r.peer_share_us[1]},
                 {"peer_step4_free_mean_share_us", r.peer_share_us[2]}, {"peer_contact_mean_share_us", r.peer_share_us[3]}, {"ours_prep_ms", r.ours_prep_ms}, {"peer_prep_ms", r.peer_prep_ms}});
  for (const DistanceRow& r : drows)
    j.push_back({{"name", r.name}, {"ours_us", r.ours.median}, {"peer", "fcl distance"}, {"peer_us", r.peer.median},
                 {"ratio", r.ratio()}, {"agreement", static_cast<double>(r.agree) / static_cast<double>(r.queries)},
                 {"ours_p95_us", r.ours.p95}, {"ours_mean_us", r.ours.mean}, {"peer_p95_us", r.peer.p95},
                 {"peer_mean_us", r.peer.mean}, {"mean_ratio", r.mean_ratio()}, {"queries", r.queries},
                 {"contact", r.contact}, {"disagree_containment", r.containment}, {"disagree_other", r.other},
                 {"max_relative_difference", r.max_rel}, {"mean_face_pairs", r.face_pairs},
                 {"mean_node_pairs", r.node_pairs}});
  for (const BigRow& r : big) {
    nlohmann::json row = {{"name", "big mesh preprocessing, " + std::to_string(r.faces) + " faces"},
                          {"ours_us", r.ours_ms * 1e3}, {"peer", "fcl BVHModel<OBBRSS> build"},
                          {"agreement", nullptr}, {"halvings", r.m}, {"ours_bytes_per_face", r.ours_bytes_per_face}};
    row["peer_us"] = r.peer_ms * 1e3;
    row["ratio"] = r.ours_ms / r.peer_ms;
    row["peer_bytes_per_face"] = r.peer_bytes_per_face;
    row["distance_tree_us"] = r.tree_ms * 1e3;
    row["distance_tree_bytes_per_face"] = r.tree_bytes_per_face;
    row["distance_tree_ratio"] = r.tree_ms / r.peer_ms;
    if (r.faces > 5000000) row["note"] = "ours best of 3, FCL's build once";
    j.push_back(row);
  }
  if (merge) {
    // The rows just measured replace those of the same name in the results file (the others
    // stay, in their order; new ones go at the end).
    nlohmann::json old = nlohmann::json::array();
    if (std::ifstream in(out); in) old = nlohmann::json::parse(in, nullptr, false);
    if (!old.is_array()) old = nlohmann::json::array();
    for (const auto& row : j) {
      auto same = std::find_if(old.begin(), old.end(), [&](const nlohmann::json& o) { return o.value("name", "") == row["name"]; });
      if (same != old.end()) *same = row;
      else old.push_back(row);
    }
    j = old;
  } else if (!only.empty()) {
    out += ".partial";  // a partial run never overwrites the committed results
  }
  std::ofstream(out) << j.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
