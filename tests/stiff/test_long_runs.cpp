// Long runs (docs/stiff-cases.md "Long runs"): 10^6 compound transformations through VAL's `:`
// keep rotation matrices orthonormal to 1e-12 (docs/kinematics.md §8) and a chain followed by its
// inverse chain returns to the start within the documented drift bound. The 10^6 DRAW moves
// through the simulator are the end-to-end case programs/stiff/long_draw.v2.
#include "interpreter/src/operators.hpp"
#include "asimov/motion/location.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace asimov;
using asimov::motion::Location;

namespace {

double orthonormality_error(const Location& t) {
  const Eigen::Matrix3d r = t.linear();
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

Location compound(const Location& a, const Location& b) {
  return std::get<Location>(interpreter::apply_binary(interpreter::ast::Op::compound, a, b));
}

}  // namespace

TEST_CASE("10^6 compound transformations stay orthonormal to 1e-12 and return to the start", "[stiff][long]") {
  // A small screw motion and its inverse; 5e5 of each.
  const Location step = motion::trans(0.1, -0.2, 0.05, 0.3, 0.7, -0.2);
  const Location back(step.inverse());
  Location a = Location::Identity();
  double worst = 0, farthest = 0;
  constexpr int kHalf = 500000;
  for (int i = 0; i < 2 * kHalf; ++i) {
    a = compound(a, i < kHalf ? step : back);
    if (i % 1000 == 999) worst = std::max(worst, orthonormality_error(a));
    farthest = std::max(farthest, a.translation().norm());
  }
  INFO("worst orthonormality error " << worst << ", final position drift " << a.translation().norm()
                                      << " mm, farthest " << farthest << " mm");
  CHECK(worst <= 1e-12);
  CHECK(orthonormality_error(a) <= 1e-12);
  // Documented drift bound: one unit roundoff of the farthest position per compound.
  CHECK(a.translation().norm() <= 2 * kHalf * std::numeric_limits<double>::epsilon() / 2 * farthest);
  CHECK(a.translation().norm() <= 1e-6);
  CHECK((a.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9);
}
