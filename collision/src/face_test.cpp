// Guigue & Devillers (2003) triangle-triangle overlap, decided from exact orientation signs
// only (predicates.hpp); no point is constructed. Degenerate and coplanar configurations go
// to small exact sub-tests: coplanar sets are decided in all three axis projections (each is
// a necessary condition, and one of them is injective on the common plane, so together they
// are exact), and zero-area triangles are tested edge by edge as the segment they are.
#include "exact_fp.hpp"  // first: no FMA contraction below
#include "face_test.hpp"

#include "face_distance.hpp"
#include "predicates.hpp"

#include <algorithm>

namespace asimov::collision {
namespace {

struct P2 {
  double x, y;
};

inline P2 drop_axis(const Vec3& v, int k) { return {v[(k + 1) % 3], v[(k + 2) % 3]}; }

inline int o2(const P2& a, const P2& b, const P2& c) { return orient2d(a.x, a.y, b.x, b.y, c.x, c.y); }

// Closed 2D segments, either possibly a point.
bool segments_intersect_2d(const P2& p0, const P2& p1, const P2& q0, const P2& q1) {
  const int a = o2(p0, p1, q0), b = o2(p0, p1, q1);
  if (a * b > 0) return false;
  const int c = o2(q0, q1, p0), d = o2(q0, q1, p1);
  if (c * d > 0) return false;
  if (a == 0 && b == 0 && c == 0 && d == 0) {
    // All on one line (or points): the closed intervals must overlap on both axes.
    return std::max(std::min(p0.x, p1.x), std::min(q0.x, q1.x)) <= std::min(std::max(p0.x, p1.x), std::max(q0.x, q1.x)) &&
           std::max(std::min(p0.y, p1.y), std::min(q0.y, q1.y)) <= std::min(std::max(p0.y, p1.y), std::max(q0.y, q1.y));
  }
  return true;
}

// Closed point in a closed 2D triangle of non-zero area with orientation sign `s`.
bool point_in_triangle_2d(const P2& p, const std::array<P2, 3>& t, int s) {
  return o2(t[0], t[1], p) * s >= 0 && o2(t[1], t[2], p) * s >= 0 && o2(t[2], t[0], p) * s >= 0;
}

// Convex hulls of three 2D points each (repeats and collinear points allowed): they meet iff
// two boundary edges meet or one hull holds a vertex of the other.
bool hulls_overlap_2d(const std::array<P2, 3>& a, const std::array<P2, 3>& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (segments_intersect_2d(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])) return true;
  if (const int sa = o2(a[0], a[1], a[2]); sa != 0 && point_in_triangle_2d(b[0], a, sa)) return true;
  if (const int sb = o2(b[0], b[1], b[2]); sb != 0 && point_in_triangle_2d(a[0], b, sb)) return true;
  return false;
}

// Precondition: all six points lie in one plane (or line).
bool coplanar_overlap(const TriangleVerts& t1, const TriangleVerts& t2) {
  for (int k = 0; k < 3; ++k) {
    const std::array<P2, 3> a{drop_axis(t1[0], k), drop_axis(t1[1], k), drop_axis(t1[2], k)};
    const std::array<P2, 3> b{drop_axis(t2[0], k), drop_axis(t2[1], k), drop_axis(t2[2], k)};
    if (!hulls_overlap_2d(a, b)) return false;
  }
  return true;
}

bool is_collinear(const TriangleVerts& t) {
  for (int k = 0; k < 3; ++k)
    if (o2(drop_axis(t[0], k), drop_axis(t[1], k), drop_axis(t[2], k)) != 0) return false;
  return true;
}

// Segment against a triangle of non-zero area.
bool segment_meets_proper_triangle(const Vec3& s0, const Vec3& s1, const TriangleVerts& t) {
  const int a = orient3d(t[0], t[1], t[2], s0), b = orient3d(t[0], t[1], t[2], s1);
  if (a * b > 0) return false;
  if (a == 0 && b == 0) return coplanar_overlap({s0, s1, s1}, t);
  // The line s0s1 crosses the plane inside the segment; it passes through the closed
  // triangle iff it does not see the three edges with strictly mixed orientations.
  const int e0 = orient3d(s0, s1, t[0], t[1]);
  const int e1 = orient3d(s0, s1, t[1], t[2]);
  const int e2 = orient3d(s0, s1, t[2], t[0]);
  const bool pos = e0 > 0 || e1 > 0 || e2 > 0;
  const bool neg = e0 < 0 || e1 < 0 || e2 < 0;
  return !(pos && neg);
}

// A zero-area triangle is the union of its three edges.
bool degenerate_meets(const TriangleVerts& seg, const TriangleVerts& t, bool t_degenerate) {
  for (int i = 0; i < 3; ++i) {
    const Vec3& s0 = seg[i];
    const Vec3& s1 = seg[(i + 1) % 3];
    if (t_degenerate) {
      for (int j = 0; j < 3; ++j)
        if (segments_intersect(s0, s1, t[j], t[(j + 1) % 3])) return true;
    } else if (segment_meets_proper_triangle(s0, s1, t)) {
      return true;
    }
  }
  return false;
}

// Both triangles proper and not coplanar: p1 is alone on its side of T2's plane and p2 on its
// side of T1's plane, oriented so that the intervals on the common line overlap iff neither
// orientation below is positive (Guigue & Devillers, eq. 3). Zero counts as touching.
bool check_min_max(const Vec3& p1, const Vec3& q1, const Vec3& r1, const Vec3& p2, const Vec3& q2,
                   const Vec3& r2) {
  if (orient3d(q1, p2, p1, q2) > 0) return false;
  if (orient3d(p1, p2, r1, r2) > 0) return false;
  return true;
}

// Puts p2 alone on its side of T1's plane, swapping q2/r2 when that keeps p1 positive.
bool tri_tri_3d(const Vec3& p1, const Vec3& q1, const Vec3& r1, const Vec3& p2, const Vec3& q2,
                const Vec3& r2, int dp2, int dq2, int dr2, const TriangleVerts& t1,
                const TriangleVerts& t2) {
  if (dp2 > 0) {
    if (dq2 > 0) return check_min_max(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0) return check_min_max(p1, r1, q1, q2, r2, p2);
    return check_min_max(p1, q1, r1, p2, q2, r2);
  }
  if (dp2 < 0) {
    if (dq2 < 0) return check_min_max(p1, q1, r1, r2, p2, q2);
    if (dr2 < 0) return check_min_max(p1, q1, r1, q2, r2, p2);
    return check_min_max(p1, r1, q1, p2, q2, r2);
  }
  if (dq2 < 0) {
    if (dr2 >= 0) return check_min_max(p1, r1, q1, q2, r2, p2);
    return check_min_max(p1, q1, r1, p2, q2, r2);
  }
  if (dq2 > 0) {
    if (dr2 > 0) return check_min_max(p1, r1, q1, p2, q2, r2);
    return check_min_max(p1, q1, r1, q2, r2, p2);
  }
  if (dr2 > 0) return check_min_max(p1, q1, r1, r2, p2, q2);
  if (dr2 < 0) return check_min_max(p1, r1, q1, r2, p2, q2);
  return coplanar_overlap(t1, t2);  // unreachable: coplanar pairs are handled by the caller
}

}  // namespace

bool segments_intersect(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  if (orient3d(p0, p1, q0, q1) != 0) return false;
  for (int k = 0; k < 3; ++k)
    if (!segments_intersect_2d(drop_axis(p0, k), drop_axis(p1, k), drop_axis(q0, k), drop_axis(q1, k)))
      return false;
  return true;
}

bool segment_intersects_triangle(const Vec3& s0, const Vec3& s1, const TriangleVerts& t) {
  if (is_collinear(t)) return degenerate_meets(t, {s0, s1, s1}, true);
  return segment_meets_proper_triangle(s0, s1, t);
}

bool triangles_intersect(const TriangleVerts& t1, const TriangleVerts& t2) {
  // Disjoint bounding boxes: min/max involve no rounding, so this rejection is exact, and it
  // spares most of the orientation predicates in step 4.
  for (int k = 0; k < 3; ++k) {
    if (std::min({t1[0][k], t1[1][k], t1[2][k]}) > std::max({t2[0][k], t2[1][k], t2[2][k]})) return false;
    if (std::min({t2[0][k], t2[1][k], t2[2][k]}) > std::max({t1[0][k], t1[1][k], t1[2][k]})) return false;
  }
  const Vec3 &p1 = t1[0], &q1 = t1[1], &r1 = t1[2];
  const Vec3 &p2 = t2[0], &q2 = t2[1], &r2 = t2[2];

  const int dp1 = orient3d(p2, q2, r2, p1), dq1 = orient3d(p2, q2, r2, q1), dr1 = orient3d(p2, q2, r2, r1);
  if (dp1 * dq1 > 0 && dp1 * dr1 > 0) return false;
  if (dp1 == 0 && dq1 == 0 && dr1 == 0) {
    // Either T2 has no plane (zero area) or T1 lies in T2's plane.
    if (is_collinear(t2)) return degenerate_meets(t2, t1, is_collinear(t1));
    return coplanar_overlap(t1, t2);
  }
  // Here T2 has non-zero area.
  const int dp2 = orient3d(p1, q1, r1, p2), dq2 = orient3d(p1, q1, r1, q2), dr2 = orient3d(p1, q1, r1, r2);
  if (dp2 * dq2 > 0 && dp2 * dr2 > 0) return false;
  // All zero although T1 is not in T2's plane: T1 has zero area.
  if (dp2 == 0 && dq2 == 0 && dr2 == 0) return degenerate_meets(t1, t2, false);

  // Put p1 alone on its side of T2's plane (cyclic permutations keep T1's orientation).
  if (dp1 > 0) {
    if (dq1 > 0) return tri_tri_3d(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, t1, t2);
    if (dr1 > 0) return tri_tri_3d(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, t1, t2);
    return tri_tri_3d(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, t1, t2);
  }
  if (dp1 < 0) {
    if (dq1 < 0) return tri_tri_3d(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, t1, t2);
    if (dr1 < 0) return tri_tri_3d(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, t1, t2);
    return tri_tri_3d(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, t1, t2);
  }
  if (dq1 < 0) {
    if (dr1 >= 0) return tri_tri_3d(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2, t1, t2);
    return tri_tri_3d(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2, t1, t2);
  }
  if (dq1 > 0) {
    if (dr1 > 0) return tri_tri_3d(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2, t1, t2);
    return tri_tri_3d(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2, t1, t2);
  }
  if (dr1 > 0) return tri_tri_3d(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2, t1, t2);
  if (dr1 < 0) return tri_tri_3d(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2, t1, t2);
  return coplanar_overlap(t1, t2);  // unreachable: handled above
}

Vec3 contact_point(const TriangleVerts& t1, const TriangleVerts& t2) {
  // An edge of one triangle that crosses the other's plane at a single point inside it.
  for (int which = 0; which < 2; ++which) {
    const TriangleVerts& a = which == 0 ? t1 : t2;
    const TriangleVerts& b = which == 0 ? t2 : t1;
    if (is_collinear(b)) continue;
    const Vec3 n = (b[1] - b[0]).cross(b[2] - b[0]);
    for (int i = 0; i < 3; ++i) {
      const Vec3& s0 = a[i];
      const Vec3& s1 = a[(i + 1) % 3];
      const int o0 = orient3d(b[0], b[1], b[2], s0), o1 = orient3d(b[0], b[1], b[2], s1);
      if (o0 * o1 > 0 || (o0 == 0 && o1 == 0)) continue;
      if (!segment_meets_proper_triangle(s0, s1, b)) continue;
      if (o0 == 0) return s0;
      if (o1 == 0) return s1;
      const double d0 = n.dot(s0 - b[0]), d1 = n.dot(s1 - b[0]);
      const double t = std::clamp(d0 / (d0 - d1), 0.0, 1.0);
      return s0 + t * (s1 - s0);
    }
  }
  // In-plane contact: a vertex inside the other triangle, or two crossing edges.
  Vec3 on1, on2;
  triangle_closest_points(t1, t2, on1, on2);
  return 0.5 * (on1 + on2);
}

}  // namespace asimov::collision
