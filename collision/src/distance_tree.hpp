// Distance query, step 3 [ours, after PQP/FCL's bounding-volume trees]: a per-body binary tree
// of oriented boxes over the faces, built lazily on the body's first distance query (the
// halvings tree's voxels hold many faces each and their content boxes are loose; docs/collision.md
// §11). Nodes are PCA boxes in float, leaves a few faces. Header-only descent so the engine's
// leaf visitor inlines.
#pragma once
#include "asimov/collision/polyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace asimov::collision {

// An oriented box of the body's local frame: every point x of the node's faces has
// |axis_k . (x - c)| <= h_k with the float axis and centre as stored (exactly, up to a pad for
// the double rounding of the build). The axes are orthonormal only to float rounding; the
// bound below allows for that.
struct DistanceNode {
  float c[3];
  float h[3];
  float axis[3][3];      // axis[k]: the k-th box axis (unit to float rounding)
  std::uint32_t first;   // inner node: left child index; leaf: first face in DistanceTree::faces
  std::uint32_t second;  // inner node: right child index; leaf: kLeaf | face count
  static constexpr std::uint32_t kLeaf = 0x80000000u;
  bool leaf() const { return (second & kLeaf) != 0; }
  std::uint32_t count() const { return second & ~kLeaf; }
  double size() const { return static_cast<double>(h[0]) + h[1] + h[2]; }
};

struct DistanceTree {
  std::vector<DistanceNode> nodes;   // nodes[0] is the root; empty when the mesh has no face
  std::vector<std::uint32_t> faces;  // face indices, each leaf's a contiguous run
  std::size_t bytes() const { return nodes.capacity() * sizeof(DistanceNode) + faces.capacity() * sizeof(std::uint32_t); }
};

// Faces per leaf (at most): the face pairs of two leaves are cheap to bound one by one
// (engine.cpp), and fewer nodes mean fewer node pairs; a 10^6-face body's tree is about 30
// bytes per face (docs/collision.md §13).
constexpr std::uint32_t kDistanceLeafFaces = 8;

DistanceTree build_distance_tree(const Polyhedron& mesh, std::uint32_t leaf_faces = kDistanceLeafFaces);

// Lower bound on the distance of two nodes' contents, X of body A's tree and Y of B's, for one
// relative pose (a = r b + t): the distance of X to the axis-aligned box of Y in X's axes, and of
// Y to that of X in Y's axes (the larger), less the pair's rounding slack (2 eps_r) and a relative
// 4e-6 of the sizes in play for the float axes (orthonormal only to 1e-7; docs/collision.md §11).
struct DistanceBound {
  Mat3 r;
  Vec3 t;
  double slack;
  DistanceBound(const Pose& a_from_b, double slack_mm) : r(a_from_b.linear()), t(a_from_b.translation()), slack(slack_mm) {}

  // One of the two nodes as seen from the other's frame, computed once per expansion (both
  // children of the split node are tested against it). Splitting X: Y's axes and centre in A's
  // frame. Splitting Y: X's axes in B's frame (rows) and a_k . (t - cx).
  struct Fixed {
    double v[3][3];
    double w[3];
  };
  Fixed fixed_y(const DistanceNode& y) const {
    Fixed f;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        f.v[j][i] = r(i, 0) * y.axis[j][0] + r(i, 1) * y.axis[j][1] + r(i, 2) * y.axis[j][2];
    for (int i = 0; i < 3; ++i) f.w[i] = r(i, 0) * y.c[0] + r(i, 1) * y.c[1] + r(i, 2) * y.c[2] + t[i];
    return f;
  }
  Fixed fixed_x(const DistanceNode& x) const {
    Fixed f;
    const double d[3] = {t[0] - x.c[0], t[1] - x.c[1], t[2] - x.c[2]};
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) f.v[k][j] = x.axis[k][0] * r(0, j) + x.axis[k][1] * r(1, j) + x.axis[k][2] * r(2, j);
      f.w[k] = x.axis[k][0] * d[0] + x.axis[k][1] * d[1] + x.axis[k][2] * d[2];
    }
    return f;
  }
  // Two lanes, one per child of the split node (GCC/Clang vector extensions: SSE2 on x86-64,
  // no target flags): both children's bounds at once.
  using V2 = double __attribute__((vector_size(16)));
  using M2 = std::int64_t __attribute__((vector_size(16)));
  static V2 vabs(V2 v) { return reinterpret_cast<V2>(reinterpret_cast<M2>(v) & 0x7fffffffffffffffLL); }
  static V2 vmax(V2 a, V2 b) {
    const M2 m = a > b;
    return reinterpret_cast<V2>((reinterpret_cast<M2>(a) & m) | (reinterpret_cast<M2>(b) & ~m));
  }
  static V2 pos(V2 g) { return vmax(g, V2{0, 0}); }

  // Children x1, x2 of the split node X against the fixed Y (fixed_y(y)).
  [[gnu::always_inline]] V2 x_children(const DistanceNode& x1, const DistanceNode& x2, const DistanceNode& y,
                                       const Fixed& fy) const {
    V2 tx[3], m[3][3], hx[3], hy[3];
    V2 d[3];
    for (int i = 0; i < 3; ++i) d[i] = V2{fy.w[i] - x1.c[i], fy.w[i] - x2.c[i]};
    for (int k = 0; k < 3; ++k) {
      const V2 a0{x1.axis[k][0], x2.axis[k][0]}, a1{x1.axis[k][1], x2.axis[k][1]}, a2{x1.axis[k][2], x2.axis[k][2]};
      tx[k] = a0 * d[0] + a1 * d[1] + a2 * d[2];
      for (int j = 0; j < 3; ++j) m[k][j] = a0 * fy.v[j][0] + a1 * fy.v[j][1] + a2 * fy.v[j][2];
      hx[k] = V2{x1.h[k], x2.h[k]};
      hy[k] = V2{0, 0} + static_cast<double>(y.h[k]);
    }
    return finish(tx, m, hx, hy);
  }
  // Children y1, y2 of the split node Y against the fixed X (fixed_x(x)).
  [[gnu::always_inline]] V2 y_children(const DistanceNode& x, const DistanceNode& y1, const DistanceNode& y2,
                                       const Fixed& fx) const {
    V2 tx[3], m[3][3], hx[3], hy[3];
    const V2 c0{y1.c[0], y2.c[0]}, c1{y1.c[1], y2.c[1]}, c2{y1.c[2], y2.c[2]};
    V2 b[3][3];
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) b[j][i] = V2{y1.axis[j][i], y2.axis[j][i]};
    for (int k = 0; k < 3; ++k) {
      tx[k] = fx.v[k][0] * c0 + fx.v[k][1] * c1 + fx.v[k][2] * c2 + fx.w[k];
      for (int j = 0; j < 3; ++j) m[k][j] = fx.v[k][0] * b[j][0] + fx.v[k][1] * b[j][1] + fx.v[k][2] * b[j][2];
      hx[k] = V2{0, 0} + static_cast<double>(x.h[k]);
      hy[k] = V2{y1.h[k], y2.h[k]};
    }
    return finish(tx, m, hx, hy);
  }
  // The root pair (lane 0).
  double operator()(const DistanceNode& x, const DistanceNode& y) const { return x_children(x, x, y, fixed_y(y))[0]; }

  // tx: Y's centre less X's in X's axes; m[k][j] = a_k . (r b_j); half sides of X and Y.
  [[gnu::always_inline]] V2 finish(const V2 (&tx)[3], const V2 (&m)[3][3], const V2 (&hx)[3], const V2 (&hy)[3]) const {
    V2 am[3][3];
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) am[k][j] = vabs(m[k][j]);
    V2 s1{0, 0}, s2{0, 0}, dd{0, 0}, sup{0, 0}, l1{0, 0};
    for (int k = 0; k < 3; ++k) {
      const V2 at = vabs(tx[k]);
      const V2 g = pos(at - hx[k] - (am[k][0] * hy[0] + am[k][1] * hy[1] + am[k][2] * hy[2]));
      s1 += g * g;
      dd += tx[k] * tx[k];
      sup += at * hx[k];
      l1 += at + hx[k] + hy[k];
    }
    for (int j = 0; j < 3; ++j) {
      const V2 ty = vabs(m[0][j] * tx[0] + m[1][j] * tx[1] + m[2][j] * tx[2]);
      const V2 g = pos(ty - hy[j] - (am[0][j] * hx[0] + am[1][j] * hx[1] + am[2][j] * hx[2]));
      s2 += g * g;
      sup += ty * hy[j];
    }
    // The larger of the two frames' box distances; along the line of centres u = d / |d|, both
    // boxes' supports, |d| - sum |u.a_k| h_k - sum |u.b_j| h_j (tight for boxes small against
    // their distance, whatever their turn).
    const V2 s = vmax(s1, s2);
    V2 lb{0, 0}, line{0, 0};
    for (int l = 0; l < 2; ++l) {
      lb[l] = std::sqrt(s[l]);
      line[l] = dd[l] > sup[l] ? (dd[l] - sup[l]) / std::sqrt(dd[l]) : 0.0;
    }
    return vmax(lb, line) - slack - 4e-6 * l1;
  }
};

// A node pair waiting in the descent, with its bound.
struct DistancePair {
  std::uint32_t x, y;
  double lb;
};

// Best first from the roots: the pair with the smallest bound is expanded next (a heap in
// `stack`, reused between queries), splitting the larger node (or the one not a leaf) and
// keeping each child whose bound is below `best` (the cut-off at first, lowered by `leaf`); the
// descent ends when the smallest bound left is not below best. `leaf(x, y)` is called for every
// pair of leaves reached. `tests` counts the bounds computed.
template <class Leaf>
void descend_distance_tree(const DistanceTree& ta, const DistanceTree& tb, const DistanceBound& bound, const double& best,
                           std::vector<DistancePair>& stack, std::uint64_t& tests, Leaf&& leaf) {
  stack.clear();
  if (ta.nodes.empty() || tb.nodes.empty()) return;
  const double lb = bound(ta.nodes[0], tb.nodes[0]);
  ++tests;
  if (!(lb < best)) return;
  auto farther = [](const DistancePair& p, const DistancePair& q) { return p.lb > q.lb; };
  DistancePair cur{0, 0, lb};
  for (;;) {
    const DistanceNode& x = ta.nodes[cur.x];
    const DistanceNode& y = tb.nodes[cur.y];
    const bool xl = x.leaf(), yl = y.leaf();
    bool next = false;  // the nearer child goes on at once when no pair waiting is nearer
    if (xl && yl) {
      leaf(x, y);
    } else {
      const bool split_a = !xl && (yl || x.size() >= y.size());
      tests += 2;
      DistancePair p1, p2;
      if (split_a) {
        const auto lb2 = bound.x_children(ta.nodes[x.first], ta.nodes[x.second], y, bound.fixed_y(y));
        p1 = {x.first, cur.y, lb2[0]};
        p2 = {x.second, cur.y, lb2[1]};
      } else {
        const auto lb2 = bound.y_children(x, tb.nodes[y.first], tb.nodes[y.second], bound.fixed_x(x));
        p1 = {cur.x, y.first, lb2[0]};
        p2 = {cur.x, y.second, lb2[1]};
      }
      if (p2.lb < p1.lb) std::swap(p1, p2);
      if (p2.lb < best) {
        stack.push_back(p2);
        std::push_heap(stack.begin(), stack.end(), farther);
      }
      if (p1.lb < best) {
        if (stack.empty() || p1.lb <= stack.front().lb) {
          cur = p1;
          next = true;
        } else {
          stack.push_back(p1);
          std::push_heap(stack.begin(), stack.end(), farther);
        }
      }
    }
    if (next) continue;
    if (stack.empty()) return;
    std::pop_heap(stack.begin(), stack.end(), farther);
    cur = stack.back();
    stack.pop_back();
    if (!(cur.lb < best)) return;  // the smallest bound left: nothing nearer remains
  }
}

}  // namespace asimov::collision
