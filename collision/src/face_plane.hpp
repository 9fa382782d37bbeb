// A cheap sound prefilter for step 4 [ours]: each world face's plane (normal and the absolute
// products that bound its rounding) is computed once per pose, so "all three vertices of the
// other triangle strictly on one side" costs three dot products instead of three orient3d calls.
// It only ever answers "separated" when the exact signs agree; otherwise the exact test decides.
// Built with -ffp-contract=off (engine.cpp includes it; collision/CMakeLists.txt): the bound
// below is for separately rounded products. Assumes no overflow/underflow, as predicates.hpp.
#pragma once
#include "face_test.hpp"

#include <cfloat>
#include <cmath>

// Not exact_fp.hpp: its optimize pragma would split engine.cpp's functions into two option sets
// (and stop inlining between them); CMake's -ffp-contract=off covers engine.cpp.
#if defined(__FAST_MATH__)
#error "the plane prefilter's error bound needs IEEE arithmetic: no fast-math"
#endif
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "the plane prefilter needs FLT_EVAL_METHOD == 0 (SSE2 doubles)"
#endif

namespace asimov::collision {

struct FacePlane {
  Vec3 n;     // (q - p) x (r - p), in double (p, q, r the world vertices)
  Vec3 nabs;  // per component |u_y v_z| + |u_z v_y| (and cyclic): the permanent's factors
};

inline FacePlane face_plane(const TriangleVerts& t) {
  const Vec3 u = t[1] - t[0], v = t[2] - t[0];
  FacePlane f;
  f.n = Vec3(u.y() * v.z() - u.z() * v.y(), u.z() * v.x() - u.x() * v.z(), u.x() * v.y() - u.y() * v.x());
  f.nabs = Vec3(std::fabs(u.y() * v.z()) + std::fabs(u.z() * v.y()), std::fabs(u.z() * v.x()) + std::fabs(u.x() * v.z()),
                std::fabs(u.x() * v.y()) + std::fabs(u.y() * v.x()));
  return f;
}

// Side of x relative to the plane of t (p = t[0]): +1 or -1 only when the sign of the exact
// determinant (x - p) . ((q - p) x (r - p)) is certain, else 0. d = a . n is that determinant
// with each of its six monomials rounded at most 8 times (3 differences, 2 products, 1 in the
// cross product, 2 in the sum), so |d - exact| <= gamma_8 * permanent; 12 units of 2^-53 of the
// computed permanent covers that with room for the permanent's own rounding.
inline int plane_side(const FacePlane& f, const Vec3& p, const Vec3& x) {
  constexpr double kBound = 12 * (DBL_EPSILON / 2);
  const double ax = x.x() - p.x(), ay = x.y() - p.y(), az = x.z() - p.z();
  const double d = ax * f.n.x() + ay * f.n.y() + az * f.n.z();
  const double perm = std::fabs(ax) * f.nabs.x() + std::fabs(ay) * f.nabs.y() + std::fabs(az) * f.nabs.z();
  const double b = kBound * perm;
  return (d > b) - (d < -b);
}

// True only when t2's three vertices lie strictly on one side of t1's plane (exactly, as the
// signs above are certain): triangles_intersect(t1, t2) is then false.
inline bool plane_separates(const FacePlane& f1, const TriangleVerts& t1, const TriangleVerts& t2) {
  const int s0 = plane_side(f1, t1[0], t2[0]);
  if (s0 == 0) return false;
  return plane_side(f1, t1[0], t2[1]) == s0 && plane_side(f1, t1[0], t2[2]) == s0;
}

}  // namespace asimov::collision
