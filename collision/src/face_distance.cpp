#include "face_distance.hpp"

#include <algorithm>
#include <cmath>

namespace asimov::collision {
namespace {

Vec3 segment_closest_point(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0) return a;
  return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

}  // namespace

// Ericson, Real-Time Collision Detection (2005), 5.1.9, with the degenerate branches kept.
double segment_closest_points(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                              Vec3& on_p, Vec3& on_q) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) {
    s = t = 0;
  } else if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  on_p = p0 + s * d1;
  on_q = q0 + t * d2;
  return (on_p - on_q).squaredNorm();
}

Vec3 triangle_closest_point(const Vec3& p, const TriangleVerts& t) {
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double nn = n.squaredNorm();
  if (nn > 0) {
    // Projection onto the plane, kept when it lies inside (all edge sides agree with n).
    const Vec3 q = p - (n.dot(p - t[0]) / nn) * n;
    if (n.dot((t[1] - t[0]).cross(q - t[0])) >= 0 && n.dot((t[2] - t[1]).cross(q - t[1])) >= 0 &&
        n.dot((t[0] - t[2]).cross(q - t[2])) >= 0)
      return q;
  }
  Vec3 best = segment_closest_point(p, t[0], t[1]);
  double best_d = (best - p).squaredNorm();
  for (int i = 1; i < 3; ++i) {
    const Vec3 c = segment_closest_point(p, t[i], t[(i + 1) % 3]);
    if (const double d = (c - p).squaredNorm(); d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

double triangle_closest_points(const TriangleVerts& t1, const TriangleVerts& t2, Vec3& on1, Vec3& on2) {
  double best = -1;
  auto keep = [&](double d, const Vec3& a, const Vec3& b) {
    if (best < 0 || d < best) {
      best = d;
      on1 = a;
      on2 = b;
    }
  };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec3 a, b;
      const double d = segment_closest_points(t1[i], t1[(i + 1) % 3], t2[j], t2[(j + 1) % 3], a, b);
      keep(d, a, b);
    }
  for (int i = 0; i < 3; ++i) {
    const Vec3 b = triangle_closest_point(t1[i], t2);
    keep((b - t1[i]).squaredNorm(), t1[i], b);
    const Vec3 a = triangle_closest_point(t2[i], t1);
    keep((a - t2[i]).squaredNorm(), a, t2[i]);
  }
  return best;
}

bool triangles_within(const TriangleVerts& t1, const TriangleVerts& t2, double clearance, double& distance,
                      Vec3& on1, Vec3& on2) {
  for (int k = 0; k < 3; ++k) {
    if (std::min({t1[0][k], t1[1][k], t1[2][k]}) > std::max({t2[0][k], t2[1][k], t2[2][k]}) + clearance) return false;
    if (std::min({t2[0][k], t2[1][k], t2[2][k]}) > std::max({t1[0][k], t1[1][k], t1[2][k]}) + clearance) return false;
  }
  const double d2 = triangle_closest_points(t1, t2, on1, on2);
  if (d2 > clearance * clearance) return false;
  distance = std::sqrt(d2);
  return true;
}

}  // namespace asimov::collision
