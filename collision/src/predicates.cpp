// Orientation predicates. The filter is Shewchuk's (1997) first-stage bound; when the double
// result is inside it, the determinant is summed exactly from products of the input
// coordinates as a non-overlapping floating-point expansion (two_sum, Dekker two_product).
// Assumes IEEE doubles, round-to-nearest, no FMA contraction (this file is built with
// -ffp-contract=off) and no overflow/underflow of coordinate products.
#include "exact_fp.hpp"  // first: no FMA contraction below
#include "predicates.hpp"

#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <utility>

namespace asimov::collision {
namespace {

constexpr double kEps = DBL_EPSILON / 2;  // 2^-53, half an ulp of 1
constexpr double kCcwBound = (3.0 + 16.0 * kEps) * kEps;
constexpr double kO3dBound = (7.0 + 56.0 * kEps) * kEps;
constexpr double kSplitter = 134217729.0;  // 2^27 + 1, Dekker's split constant

// a + b = x + y exactly, |y| <= ulp(x)/2.
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

inline void split(double a, double& hi, double& lo) {
  const double c = kSplitter * a;
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}

// a * b = x + y exactly (Dekker; deliberately not fma, see the file comment).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  const double e1 = x - ahi * bhi;
  const double e2 = e1 - alo * bhi;
  const double e3 = e2 - ahi * blo;
  y = alo * blo - e3;
}

// A non-overlapping expansion, smallest component first, zeros eliminated. Adding one
// double at a time (Shewchuk's Grow-Expansion) keeps it non-overlapping, so the sign of the
// sum is the sign of the last component.
template <std::size_t N>
struct Expansion {
  std::array<double, N> c{};
  std::size_t n = 0;

  void add(double b) {
    double q = b;
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double sum, err;
      two_sum(q, c[i], sum, err);
      q = sum;
      if (err != 0) c[k++] = err;
    }
    if (q != 0 || k == 0) c[k++] = q;
    n = k;
  }
  // Adds the exact product a*b*s (four doubles).
  void add_product(double a, double b, double s) {
    double x, y, x1, y1, x2, y2;
    two_product(a, b, x, y);
    two_product(x, s, x1, y1);
    two_product(y, s, x2, y2);
    add(y2);
    add(x2);
    add(y1);
    add(x1);
  }
  void add_product(double a, double b) {
    double x, y;
    two_product(a, b, x, y);
    add(y);
    add(x);
  }
  int sign() const {
    for (std::size_t i = n; i-- > 0;)
      if (c[i] != 0) return c[i] > 0 ? 1 : -1;
    return 0;
  }
};

inline int sign_of(double d) { return (d > 0) - (d < 0); }

}  // namespace

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  // det[[ax ay 1],[bx by 1],[cx cy 1]] expanded into its six coordinate products.
  Expansion<16> e;
  e.add_product(ax, by);
  e.add_product(-ax, cy);
  e.add_product(bx, cy);
  e.add_product(-bx, ay);
  e.add_product(cx, ay);
  e.add_product(-cx, by);
  return e.sign();
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // det[b-a; c-a; d-a] = -det4[(a,1);(b,1);(c,1);(d,1)]; the 4x4 determinant is the signed
  // sum over the 24 permutations p of P[p0].x * P[p1].y * P[p2].z.
  const std::array<const Vec3*, 4> pts{&a, &b, &c, &d};
  Expansion<128> e;
  std::array<int, 4> p{0, 1, 2, 3};
  for (int n = 0; n < 24; ++n) {
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += p[i] > p[j];
    const double s = (inversions % 2 == 0) ? -1.0 : 1.0;  // minus: we want -det4
    e.add_product(s * pts[p[0]]->x(), pts[p[1]]->y(), pts[p[2]]->z());
    // next permutation in lexicographic order
    int i = 2;
    while (i >= 0 && p[i] > p[i + 1]) --i;
    if (i < 0) break;
    int j = 3;
    while (p[j] < p[i]) --j;
    std::swap(p[i], p[j]);
    for (int l = i + 1, r = 3; l < r; ++l, --r) std::swap(p[l], p[r]);
  }
  return e.sign();
}

int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double left = (ax - cx) * (by - cy);
  const double right = (ay - cy) * (bx - cx);
  const double det = left - right;
  double sum;
  if (left > 0) {
    if (right <= 0) return sign_of(det);
    sum = left + right;
  } else if (left < 0) {
    if (right >= 0) return sign_of(det);
    sum = -left - right;
  } else {
    return sign_of(det);
  }
  const double bound = kCcwBound * sum;
  if (det >= bound || -det >= bound) return sign_of(det);
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Shewchuk's orient3d(a, b, c, d) = det[a-d; b-d; c-d] = -ours.
  const double adx = a.x() - d.x(), bdx = b.x() - d.x(), cdx = c.x() - d.x();
  const double ady = a.y() - d.y(), bdy = b.y() - d.y(), cdy = c.y() - d.y();
  const double adz = a.z() - d.z(), bdz = b.z() - d.z(), cdz = c.z() - d.z();
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  // Zero permanent: every product is an exact zero (no underflow assumed), so det is 0.
  if (permanent == 0) return 0;
  const double bound = kO3dBound * permanent;
  if (det > bound || -det > bound) return -sign_of(det);
  return orient3d_exact(a, b, c, d);
}

}  // namespace asimov::collision
