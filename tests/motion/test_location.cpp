// TRANS / DECOMPOSE (dialect §4): the three decomposition cases and the required round trips.
#include "asimov/motion/location.hpp"

#include <catch2/catch.hpp>
#include <random>

using namespace asimov::motion;

TEST_CASE("TRANS is ZYZ and the identity at zero", "[location]") {
  CHECK(trans(0, 0, 0, 0, 0, 0).isApprox(Location::Identity(), 0));
  const Location t = trans(1, 2, 3, 90, 0, 0);
  CHECK(t.translation().isApprox(asimov::collision::Vec3(1, 2, 3)));
  CHECK((t.linear() * asimov::collision::Vec3::UnitX() - asimov::collision::Vec3::UnitY()).norm() < 1e-15);
  // Pitch about the new Y: approach (Z column) = (co sa, so sa, ca).
  const Location u = trans(0, 0, 0, 30, 40, 50);
  const double d = 3.14159265358979323846 / 180;
  CHECK(u.linear()(0, 2) == Approx(std::cos(30 * d) * std::sin(40 * d)));
  CHECK(u.linear()(1, 2) == Approx(std::sin(30 * d) * std::sin(40 * d)));
  CHECK(u.linear()(2, 2) == Approx(std::cos(40 * d)));
  CHECK(u.linear()(2, 0) == Approx(-std::sin(40 * d) * std::cos(50 * d)));
}

TEST_CASE("DECOMPOSE canonical forms", "[location]") {
  const Xyzoat a = decompose(trans(0, 0, 0, 90, 180, 0));  // listed case
  CHECK(a[3] == Approx(0).margin(1e-12));
  CHECK(a[4] == Approx(180));
  CHECK(a[5] == Approx(-90));
  const Xyzoat b = decompose(trans(5, 6, 7, 20, 0, 30));  // pitch 0: o = 0, t = o + t
  CHECK(b[0] == 5);
  CHECK(b[3] == 0);
  CHECK(b[4] == 0);
  CHECK(b[5] == Approx(50));
  const Xyzoat c = decompose(trans(0, 0, 0, -180, 30, -180));  // -180 is reported as 180
  CHECK(c[3] == Approx(180));
  CHECK(c[5] == Approx(180));
  CHECK(c[4] == Approx(30));
}

TEST_CASE("TRANS/DECOMPOSE round trips", "[location][random]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ang(-180, 180), pitch(0.001, 179.999), pos(-2000, 2000);
  double worst_m = 0, worst_a = 0;
  for (int i = 0; i < 20000; ++i) {
    const double o = ang(rng), a = pitch(rng), t = ang(rng);
    const Location l = trans(pos(rng), pos(rng), pos(rng), o, a, t);
    const Xyzoat d = decompose(l);
    worst_m = std::max(worst_m, (trans(d).matrix() - l.matrix()).cwiseAbs().maxCoeff());
    auto diff = [](double x, double y) { return std::abs(std::remainder(x - y, 360.0)); };
    worst_a = std::max({worst_a, diff(d[3], o), diff(d[4], a), diff(d[5], t)});
    const bool canonical = d[3] > -180 && d[3] <= 180 && d[5] > -180 && d[5] <= 180 && d[4] >= 0 && d[4] <= 180;
    if (!canonical) CHECK(canonical);
  }
  // Singular pitches: matrix round trip still holds.
  for (double a : {0.0, 180.0})
    for (double o = -170; o <= 180; o += 37)
      worst_m = std::max(worst_m, (trans(decompose(trans(1, 2, 3, o, a, 20))).matrix() - trans(1, 2, 3, o, a, 20).matrix())
                                      .cwiseAbs()
                                      .maxCoeff());
  WARN("TRANS(DECOMPOSE) max matrix error " << worst_m << ", DECOMPOSE(TRANS) max angle error " << worst_a << " deg");
  CHECK(worst_m < 1e-12);
  CHECK(worst_a < 1e-9);
}
