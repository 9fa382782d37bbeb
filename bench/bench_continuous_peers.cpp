// Continuous collision against peers on the thin-plate suite (docs/collision.md §12): a blade on
// an arm rotating about the z axis (what joint 1 does to the tool) sweeps through a thin plate
// standing in its path; the sweep is cut into windows of step_mm of arc (at the blade's outer
// edge) and each window asks one continuous query. Plates 0.01, 0.1, 1 mm x blades 0.05, 0.5,
// 1 mm x step_mm 1, 5, 20 x 12 start phases = 324 runs, as tests/stiff/test_thin.cpp.
//
// What each method checks between the window's two poses (they are not the same motion):
// - ours: ContinuousChecker (motion/src/continuous.*) on the rotation itself (poses on the arc,
//   the motion bound |dtheta| * the largest radius), contact instant to 1e-6 s;
// - FCL 0.7 continuousCollide, conservative advancement, BVHModel<RSS> meshes, with the screw
//   motion (CCDM_SCREW: for a rotation about a fixed axis this is the rotation itself) and the
//   linear interpolation motion (CCDM_LINEAR: the body's reference point on the chord, its
//   rotation interpolated), toc_err 1e-4 of the window, at most 10 iterations (FCL's defaults
//   but the solver);
// - FCL naive (CCDC_NAIVE, CCDM_LINEAR): discrete collide() at 10 interpolated poses;
// - Bullet 3.24 btContinuousConvexCollision on btBoxShape (margin 0): a convex cast with the
//   box's centre moving on the chord and its rotation interpolated (btTransformUtil), what
//   MoveIt's Bullet checker's casts do.
// A run misses when no window reports the contact; the time-of-contact error is against the
// analytic first contact (the blade's inner leading edge meeting the plate's face). us per
// query: wall time of each window's query, median over all windows of all runs.
// Writes bench/results/continuous_peers.json (or argv[1]).
#include "bench/fcl_mesh.hpp"
#include "asimov/collision/engine.hpp"
#include "asimov/collision/polyhedron.hpp"
#include "motion/src/continuous.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/NarrowPhaseCollision/btContinuousConvexCollision.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <fcl/fcl.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

using namespace asimov;
using collision::Pose;
using collision::Vec3;

namespace {

constexpr double kR = 600;        // [mm] radius of the blade's centre
constexpr double kBladeW = 60;    // radial width of the blade
constexpr double kBladeH = 100;   // height of the blade
constexpr double kPlateW = 200, kPlateH = 150;
constexpr double kOmega = 1000 / kR;  // [rad/s]: the blade's centre at 1000 mm/s

Pose arm_pose(double theta) {  // the blade (or plate) frame at angle theta about z
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix();
  p.translation() = p.linear() * Vec3(kR, 0, 0);
  return p;
}

// Angle of first contact: the blade's leading face (local y = +blade/2) at its inner edge
// (x = R - W/2, the corner that reaches the plane first while theta < 0) meets the plate's face
// y = -plate/2 (the plate's frame is arm_pose(0)).
double contact_angle(double plate, double blade) {
  const double r = kR - kBladeW / 2, h = blade / 2;
  return std::asin(-plate / 2 / std::hypot(r, h)) - std::atan2(h, r);
}

struct Method {
  std::string name, checks;
  // Window [ta, tb] (angles theta(t)): true with the contact time when it reports one.
  std::function<bool(double ta, double tb, double& t_hit)> window;
  std::function<void()> reset;
};

struct Tally {
  int runs = 0, misses = 0, early = 0;  // early: a contact reported before the true one (by > 1e-6 s)
  std::vector<double> toc_err, us;
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::shared_ptr<fcl::BVHModel<fcl::RSSd>> fcl_box(const Vec3& size) {
  return bench::fcl_mesh<fcl::RSSd>(collision::make_box(size));
}

btTransform bt(const Pose& p) {
  const Eigen::Matrix3d r = p.linear();
  btMatrix3x3 m(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  return btTransform(m, btVector3(p.translation().x(), p.translation().y(), p.translation().z()));
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out_path =
      argc > 1 ? argv[1] : std::string(ASIMOV_SOURCE_DIR) + "/bench/results/continuous_peers.json";
  const std::vector<std::string> names = {"ours (ContinuousChecker, rotation)", "FCL CA screw, meshes", "FCL CA linear, meshes",
                                          "FCL naive linear (10 poses), meshes", "Bullet convex cast", "FCL CA screw, boxes",
                                          "FCL CA linear, boxes"};
  std::vector<Tally> tally(names.size());
  std::vector<std::string> checks = {
      "the executed rotation: poses on the arc, bound |dtheta| * max radius, contact to 1e-6 s",
      "conservative advancement on RSS meshes, screw motion (= the rotation about z here)",
      "conservative advancement on RSS meshes, reference point on the chord, rotation interpolated",
      "discrete collide() at 10 poses interpolated linearly per window",
      "btContinuousConvexCollision on the boxes (convex), centre on the chord, rotation interpolated",
      "conservative advancement on fcl::Box primitives (GJK), screw motion",
      "conservative advancement on fcl::Box primitives (GJK), reference point on the chord, rotation interpolated"};
  for (const double plate : {0.01, 0.1, 1.0})
    for (const double blade : {0.05, 0.5, 1.0})
      for (const double step_mm : {1.0, 5.0, 20.0})
        for (int phase = 0; phase < 12; ++phase) {
          const double dtheta = step_mm / (kR + kBladeW / 2);
          const double theta0 = -(40 + step_mm * phase / 12) / kR;  // start ~40 mm before the plate
          const double t_true = (contact_angle(plate, blade) - theta0) / kOmega;
          const auto theta_at = [&](double t) { return theta0 + kOmega * t; };
          const Vec3 blade_size(kBladeW, blade, kBladeH), plate_size(kPlateW, plate, kPlateH);

          // Ours: one engine, the blade posed on the arc.
          collision::Engine engine;
          const collision::BodyId pb = engine.add_body({.name = "plate", .mesh = collision::make_box(plate_size), .is_static = true});
          const collision::BodyId bb = engine.add_body({.name = "blade", .mesh = collision::make_box(blade_size)});
          engine.set_pose(pb, arm_pose(0));
          motion::ContinuousChecker checker(engine, 0, 1e-6, 0);
          motion::ContinuousPath path;
          path.at = [&](double t, const robots::JointVector&) {
            robots::JointVector q(1);
            q[0] = theta_at(t);
            return q;
          };
          const double rho = std::hypot(kR + kBladeW / 2, blade / 2);  // largest radius of a blade point
          path.motion = [rho](std::size_t, double, const robots::JointVector& a, double, const robots::JointVector& b) {
            return std::abs(b[0] - a[0]) * rho;
          };
          path.jump = path.motion;
          path.pose = [&](const robots::JointVector& q, double) { engine.set_pose(bb, arm_pose(q[0])); };

          // FCL and Bullet objects.
          const auto fcl_blade = fcl_box(blade_size), fcl_plate = fcl_box(plate_size);
          const fcl::Boxd prim_blade(blade_size), prim_plate(plate_size);
          btBoxShape bt_blade(btVector3(blade_size.x() / 2, blade_size.y() / 2, blade_size.z() / 2));
          btBoxShape bt_plate(btVector3(plate_size.x() / 2, plate_size.y() / 2, plate_size.z() / 2));
          bt_blade.setMargin(0);
          bt_plate.setMargin(0);
          btVoronoiSimplexSolver simplex;
          btGjkEpaPenetrationDepthSolver epa;

          std::vector<Method> methods;
          methods.push_back({names[0], checks[0], [&](double ta, double tb, double& t_hit) {
                               robots::JointVector qa(1), qb(1);
                               qa[0] = theta_at(ta);
                               qb[0] = theta_at(tb);
                               path.pose(qb, tb);
                               const motion::ContinuousContact c = checker.verify(ta, qa, tb, qb, path);
                               t_hit = c.t_hit;
                               return c.found;
                             }, [&] { checker.reset(); }});
          const auto fcl_method = [&](fcl::CCDMotionType motion, fcl::CCDSolverType solver, bool primitives = false) {
            return [&, motion, solver, primitives](double ta, double tb, double& t_hit) {
              fcl::ContinuousCollisionRequestd req(10, 1e-4, motion, fcl::GST_LIBCCD, solver);
              fcl::ContinuousCollisionResultd res;
              const fcl::CollisionGeometryd* blade_geom = primitives ? static_cast<const fcl::CollisionGeometryd*>(&prim_blade) : fcl_blade.get();
              const fcl::CollisionGeometryd* plate_geom = primitives ? static_cast<const fcl::CollisionGeometryd*>(&prim_plate) : fcl_plate.get();
              fcl::continuousCollide(blade_geom, fcl::Transform3d(arm_pose(theta_at(ta)).matrix()),
                                     fcl::Transform3d(arm_pose(theta_at(tb)).matrix()), plate_geom,
                                     fcl::Transform3d(arm_pose(0).matrix()), fcl::Transform3d(arm_pose(0).matrix()), req, res);
              t_hit = ta + res.time_of_contact * (tb - ta);
              return res.is_collide;
            };
          };
          methods.push_back({names[1], checks[1], fcl_method(fcl::CCDM_SCREW, fcl::CCDC_CONSERVATIVE_ADVANCEMENT), [] {}});
          methods.push_back({names[2], checks[2], fcl_method(fcl::CCDM_LINEAR, fcl::CCDC_CONSERVATIVE_ADVANCEMENT), [] {}});
          methods.push_back({names[3], checks[3], fcl_method(fcl::CCDM_LINEAR, fcl::CCDC_NAIVE), [] {}});
          methods.push_back({names[4], checks[4], [&](double ta, double tb, double& t_hit) {
                               btContinuousConvexCollision cast(&bt_blade, &bt_plate, &simplex, &epa);
                               btConvexCast::CastResult res;
                               const btTransform plate_tf = bt(arm_pose(0));
                               const bool hit = cast.calcTimeOfImpact(bt(arm_pose(theta_at(ta))), bt(arm_pose(theta_at(tb))),
                                                                      plate_tf, plate_tf, res);
                               t_hit = ta + res.m_fraction * (tb - ta);
                               return hit;
                             }, [] {}});
          methods.push_back({names[5], checks[5], fcl_method(fcl::CCDM_SCREW, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, true), [] {}});
          methods.push_back({names[6], checks[6], fcl_method(fcl::CCDM_LINEAR, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, true), [] {}});

          for (std::size_t m = 0; m < methods.size(); ++m) {
            Method& method = methods[m];
            method.reset();
            Tally& tl = tally[m];
            ++tl.runs;
            bool found = false;
            const double t_end = (50.0 / kR - theta0) / kOmega;  // 50 mm past the plate
            for (int k = 0; !found; ++k) {
              const double ta = k * dtheta / kOmega, tb = (k + 1) * dtheta / kOmega;
              if (ta > t_end) break;
              double t_hit = 0;
              const auto t0 = std::chrono::steady_clock::now();
              const bool hit = method.window(ta, tb, t_hit);
              tl.us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
              if (!hit) continue;
              found = true;
              tl.toc_err.push_back(std::abs(t_hit - t_true));
              if (t_hit < t_true - 1e-6) ++tl.early;
            }
            if (!found) ++tl.misses;
          }
        }
  nlohmann::json rows = nlohmann::json::array();
  fmt::print("{:<38} {:>5} {:>7} {:>6} {:>14} {:>14} {:>10}\n", "method", "runs", "misses", "early", "toc err med s",
             "toc err max s", "us/query");
  for (std::size_t m = 0; m < names.size(); ++m) {
    const Tally& t = tally[m];
    const double err_max = t.toc_err.empty() ? NAN : *std::max_element(t.toc_err.begin(), t.toc_err.end());
    fmt::print("{:<38} {:>5} {:>7} {:>6} {:>14.3g} {:>14.3g} {:>10.2f}\n", names[m], t.runs, t.misses, t.early,
               median(t.toc_err), err_max, median(t.us));
    rows.push_back({{"name", names[m]},
                    {"checks", checks[m]},
                    {"runs", t.runs},
                    {"misses", t.misses},
                    {"early_contacts", t.early},
                    {"toc_error_median_s", median(t.toc_err)},
                    {"toc_error_max_s", err_max},
                    {"us_per_query_median", median(t.us)},
                    {"queries", t.us.size()}});
  }
  std::ofstream(out_path) << nlohmann::json{{"bench", "bench_continuous_peers"},
                                            {"suite", "thin plates 0.01/0.1/1 mm x blades 0.05/0.5/1 mm x step_mm 1/5/20 x 12 phases"},
                                            {"clock", "wall time per window query, median"},
                                            {"rows", rows}}
                                 .dump(2)
                          << '\n';
  fmt::print("wrote {}\n", out_path);
}
