// The analytic contact scenes of the work-precision reports (bench/bench_accuracy_scenes.hpp,
// docs/accuracy.md) at one coarse setting: the analytic instant lies inside the bracket every
// run reports (fixed and gap stepping), shrinks with the step without bisection and with the
// tolerance with it, and the analytic contact point is where the bisected contact is.
#include "../../bench/bench_accuracy_scenes.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace asimov;
using namespace asimov::accuracy;

namespace {

constexpr double kSlack = 1e-9;  // [s]: rounding of the inverse profile and of the IK along the line
constexpr double kNoBisection = 1e9;  // [s]: a tolerance above every sample interval

// Bisection off (tolerance 1e9) is about the checked poses alone: continuous checking off too
// (with it a contact between two checked poses is found at its instant, docs/collision.md §12).
motion::CollisionSettings settings(double step_mm, double toc_tolerance_s,
                                   motion::Stepping stepping = motion::Stepping::fixed) {
  motion::CollisionSettings s;
  s.step_mm = step_mm;
  s.toc_tolerance_s = toc_tolerance_s;
  s.stepping = stepping;
  s.continuous = toc_tolerance_s < kNoBisection;
  return s;
}

const motion::CollisionReport& contact(const motion::MotionResult& r) {
  REQUIRE(r.status == motion::MotionStatus::collision);
  return r.collision;
}

void check_bracket(const AnalyticScene& s, const motion::CollisionReport& c) {
  INFO(s.name << ": t* = " << s.t_star << ", bracket [" << c.time_free_s << ", " << c.time_s << "]");
  CHECK(c.time_free_s <= s.t_star + kSlack);
  CHECK(c.time_s >= s.t_star - kSlack);
  CHECK(std::abs(c.time_s - s.t_star) <= c.time_s - c.time_free_s + kSlack);
  CHECK((c.body_a == s.static_body || c.body_b == s.static_body));
  CHECK((c.body_a == s.moving_body || c.body_b == s.moving_body));
}

}  // namespace

TEST_CASE("accuracy scenes: the analytic contact lies in the reported bracket, plain and bisected", "[accuracy][toc]") {
  for (const AnalyticScene& s : analytic_scenes()) {
    INFO(s.name);
    REQUIRE(s.t_star > 0);
    if (s.straight) CHECK(straight_line_duration_matches(s, 8));

    // Plain stepping (bisection off: tolerance above every sample interval) at a coarse step.
    const motion::CollisionReport plain = contact(run(s, settings(8, kNoBisection)));
    check_bracket(s, plain);
    CHECK(plain.time_s - plain.time_free_s > 1e-4);  // a real sample interval, not a bisected one
    CHECK(plain.time_s > s.t_star);                  // the first colliding pose comes after t*

    // Bisected at the same step to 1e-4 s, then to 1e-7 s.
    const motion::CollisionReport coarse = contact(run(s, settings(8, 1e-4)));
    check_bracket(s, coarse);
    CHECK(coarse.time_s - coarse.time_free_s <= 1e-4);
    const motion::CollisionReport fine = contact(run(s, settings(8, 1e-7)));
    check_bracket(s, fine);
    CHECK(fine.time_s - fine.time_free_s <= 1e-7);
    CHECK(std::abs(fine.time_s - s.t_star) < std::abs(plain.time_s - s.t_star));
    // The analytic point: at 1e-7 s the tool moves < 0.1 um, J1's far points < 0.2 um.
    CHECK((fine.point - s.point_star).norm() < 1e-3);
    CHECK((plain.point - s.point_star).norm() > (fine.point - s.point_star).norm());
  }
}

TEST_CASE("accuracy scenes: without bisection the contact-instant error shrinks with the step", "[accuracy][toc]") {
  for (const AnalyticScene& s : analytic_scenes()) {
    INFO(s.name);
    const motion::CollisionReport coarse = contact(run(s, settings(8, kNoBisection)));
    const motion::CollisionReport fine = contact(run(s, settings(0.25, kNoBisection)));
    check_bracket(s, fine);
    // The bracket is one sample interval: finer steps give shorter intervals and errors.
    CHECK(fine.time_s - fine.time_free_s < (coarse.time_s - coarse.time_free_s) / 2);
    CHECK(fine.time_s - s.t_star < coarse.time_s - s.t_star);
  }
}

TEST_CASE("accuracy scenes: gap stepping brackets the analytic contact like fixed stepping", "[accuracy][toc][gap]") {
  for (const AnalyticScene& s : analytic_scenes()) {
    INFO(s.name);
    const motion::CollisionReport plain = contact(run(s, settings(8, kNoBisection, motion::Stepping::gap)));
    check_bracket(s, plain);
    CHECK(plain.time_s - plain.time_free_s > 1e-4);
    const motion::CollisionReport fine = contact(run(s, settings(1, 1e-7, motion::Stepping::gap)));
    check_bracket(s, fine);
    CHECK(fine.time_s - fine.time_free_s <= 1e-7);
    CHECK((fine.point - s.point_star).norm() < 1e-3);
    // Bisected to the same tolerance from a subset of the fixed poses: the same instant to 2 tol.
    const motion::CollisionReport fixed = contact(run(s, settings(1, 1e-7, motion::Stepping::fixed)));
    CHECK(std::abs(fine.time_s - fixed.time_s) <= 2e-7);
  }
}
