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

namespace {

// Vertex-face: when every vertex of `t` lies strictly on one side of the plane of `s`, the vertex
// nearest that plane, if its foot lies inside `s`, and its squared distance; else false.
bool vertex_face(const TriangleVerts& s, const TriangleVerts& t, double& d2, Vec3& on_s, Vec3& on_t) {
  const Vec3 e0 = s[1] - s[0], e1 = s[2] - s[1], e2 = s[0] - s[2];
  const Vec3 n = e0.cross(e1);
  const double nn = n.squaredNorm();
  if (!(nn > 0)) return false;
  const double h0 = n.dot(t[0] - s[0]), h1 = n.dot(t[1] - s[0]), h2 = n.dot(t[2] - s[0]);
  int k;
  if (h0 > 0 && h1 > 0 && h2 > 0) k = h0 <= h1 ? (h0 <= h2 ? 0 : 2) : (h1 <= h2 ? 1 : 2);
  else if (h0 < 0 && h1 < 0 && h2 < 0) k = h0 >= h1 ? (h0 >= h2 ? 0 : 2) : (h1 >= h2 ? 1 : 2);
  else return false;
  const Vec3& v = t[static_cast<std::size_t>(k)];
  // Inside: on the inner side of each edge (edge x n points inwards for n = e0 x e1).
  if (!(n.cross(e0).dot(v - s[0]) > 0 && n.cross(e1).dot(v - s[1]) > 0 && n.cross(e2).dot(v - s[2]) > 0)) return false;
  const double h = k == 0 ? h0 : k == 1 ? h1 : h2;
  on_t = v;
  on_s = v - (h / nn) * n;
  d2 = (on_s - on_t).squaredNorm();
  return true;
}

}  // namespace

double disjoint_triangle_distance2(const TriangleVerts& t1, const TriangleVerts& t2, Vec3& on1, Vec3& on2) {
  double best = INFINITY;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec3 p, q;
      const double d = segment_closest_points(t1[i], t1[(i + 1) % 3], t2[j], t2[(j + 1) % 3], p, q);
      if (d < best) {
        best = d;
        on1 = p, on2 = q;
        // p is the point of edge i nearest q and q the point of edge j nearest p, so each edge
        // lies on its own side of the slab between the planes through p and q normal to q - p;
        // with the third vertices on their sides too, the slab separates the triangles.
        const Vec3 v = q - p;
        if (v.dot(t1[(i + 2) % 3] - p) <= 0 && v.dot(t2[(j + 2) % 3] - q) >= 0) return d;
      }
    }
  double d2;
  Vec3 a, b;
  if (vertex_face(t1, t2, d2, a, b) && d2 < best) {
    on1 = a, on2 = b;
    return d2;
  }
  if (vertex_face(t2, t1, d2, b, a) && d2 < best) {
    on1 = a, on2 = b;
    return d2;
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
