// Step 3 per pose [ours]: both bodies' halvings trees (voxel_grid.hpp) descended together, so
// only pairs of subtrees whose boxes meet are visited, down to voxel pairs. Header-only so the
// engine's voxel-pair visitor inlines.
#pragma once
#include "collision/voxel_grid.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace asimov::collision {

// B's frame in A's for one pose. A node of A's tree and one of B's are tested as two oriented
// boxes on their six face normals (A's axes, then B's). Boxes are compared grown by `grow`
// (c + ε_r): the rounding of the mapping is a few ulps of the magnitudes ε_r is 64 ulps of, as
// for the minimax boxes of step 2.
struct NodeTest {
  double r[3][3]{};   // B's axes in A's frame: a = r b + t
  double ar[3][3]{};  // |r|
  double t[3]{};
  double grow = 0;

  NodeTest() = default;
  NodeTest(const Pose& a_from_b, double grow_by) : grow(grow_by) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        r[i][j] = a_from_b.linear()(i, j);
        ar[i][j] = std::fabs(r[i][j]);
      }
      t[i] = a_from_b.translation()[i];
    }
  }
};

// A pair of nodes (x of A's tree, y of B's) whose boxes meet, with what their test computed:
// y's centre and reach |r| hy in A's frame, x's centre and reach |r|^T hx in B's frame. The
// box of y in A's frame is y_centre_a +- y_reach_a, and the other way round.
struct NodePair {
  std::uint32_t x, y;
  double y_centre_a[3], y_reach_a[3];
  double x_centre_b[3], x_reach_b[3];
};

namespace detail {

// Two lanes (the two children of the node being split), GCC/Clang vector extensions: plain
// SSE2 on x86-64, no target flags.
using V2 = double __attribute__((vector_size(16)));
using M2 = long long __attribute__((vector_size(16)));
inline V2 vabs(V2 v) { return reinterpret_cast<V2>(reinterpret_cast<M2>(v) & M2{0x7fffffffffffffffLL, 0x7fffffffffffffffLL}); }

}  // namespace detail

// Depth first from the roots, splitting the node with the larger box; both children of the
// split node are tested at once (two SIMD lanes), those whose boxes do not meet the other
// node's are dropped and the nearer is visited first. `leaf(va, vb, pair)` is called for every
// pair of non-empty voxels whose content boxes meet (a voxel pair) and returns true to stop (a
// contact); descend returns whether it stopped.
template <class Leaf>
bool descend(const std::vector<TreeNode>& ta, const std::vector<TreeNode>& tb, const NodeTest& nt, Leaf&& leaf) {
  using detail::V2;
  using detail::M2;
  using detail::vabs;
  if (ta.empty() || tb.empty()) return false;
  const double g = nt.grow;
  // Each step pops one pair and pushes at most two, one level deeper: depth A + depth B + 1
  // entries; two more for the unconditional writes below.
  std::array<NodePair, 2 * kMaxHalvings + 4> stack;
  {
    const TreeNode& x = ta[0];
    const TreeNode& y = tb[0];
    NodePair& e = stack[0];
    e.x = 0;
    e.y = 0;
    bool apart = false;
    for (int i = 0; i < 3; ++i) {
      e.y_centre_a[i] = nt.t[i];
      e.y_reach_a[i] = 0;
      e.x_centre_b[i] = 0;
      e.x_reach_b[i] = 0;
      for (int j = 0; j < 3; ++j) {
        e.y_centre_a[i] += nt.r[i][j] * y.centre[j];
        e.y_reach_a[i] += nt.ar[i][j] * y.half[j];
        e.x_centre_b[i] += nt.r[j][i] * (x.centre[j] - nt.t[j]);
        e.x_reach_b[i] += nt.ar[j][i] * x.half[j];
      }
    }
    for (int i = 0; i < 3; ++i) {
      apart = apart || std::fabs(e.y_centre_a[i] - x.centre[i]) > x.half[i] + e.y_reach_a[i] + g;
      apart = apart || std::fabs(y.centre[i] - e.x_centre_b[i]) > y.half[i] + e.x_reach_b[i] + g;
    }
    if (apart) return false;
  }
  std::size_t n = 1;
  const V2 gv{g, g};
  while (n > 0) {
    const NodePair cur = stack[--n];
    const TreeNode& nx = ta[cur.x];
    const TreeNode& ny = tb[cur.y];
    if (nx.leaf() && ny.leaf()) {
      if (leaf(nx.voxel, ny.voxel, cur)) return true;
      continue;
    }
    const bool split_a = !nx.leaf() && (ny.leaf() || nx.half.squaredNorm() >= ny.half.squaredNorm());
    const std::vector<TreeNode>& tree = split_a ? ta : tb;
    const TreeNode& split = split_a ? nx : ny;
    const std::uint32_t i0 = (split_a ? cur.x : cur.y) + 1, i1 = split.second;
    const TreeNode& c0 = tree[i0];
    const TreeNode& c1 = tree[i1];
    V2 c[3], h[3];
    for (int k = 0; k < 3; ++k) {
      c[k] = V2{c0.centre[k], c1.centre[k]};
      h[k] = V2{c0.half[k], c1.half[k]};
    }
    M2 ok = M2{-1, -1};
    V2 key = V2{0, 0};
    // The children mapped into the other frame: centres and |r| h (or |r|^T h).
    V2 mc[3], mk[3];
    if (split_a) {
      for (int i = 0; i < 3; ++i) {  // A's axes: y's centre and reach were mapped already
        const V2 d = cur.y_centre_a[i] - c[i];
        ok &= vabs(d) <= h[i] + cur.y_reach_a[i] + gv;
        key += d * d;
      }
      for (int j = 0; j < 3; ++j) {  // B's axes: the children's centres mapped into B's frame
        mc[j] = nt.r[0][j] * (c[0] - nt.t[0]) + nt.r[1][j] * (c[1] - nt.t[1]) + nt.r[2][j] * (c[2] - nt.t[2]);
        mk[j] = nt.ar[0][j] * h[0] + nt.ar[1][j] * h[1] + nt.ar[2][j] * h[2];
        ok &= vabs(ny.centre[j] - mc[j]) <= ny.half[j] + mk[j] + gv;
      }
    } else {
      for (int j = 0; j < 3; ++j) {  // B's axes: x's centre and reach were mapped already
        const V2 e = c[j] - cur.x_centre_b[j];
        ok &= vabs(e) <= h[j] + cur.x_reach_b[j] + gv;
        key += e * e;
      }
      for (int i = 0; i < 3; ++i) {  // A's axes: the children's centres mapped into A's frame
        mc[i] = nt.r[i][0] * c[0] + nt.r[i][1] * c[1] + nt.r[i][2] * c[2] + nt.t[i];
        mk[i] = nt.ar[i][0] * h[0] + nt.ar[i][1] * h[1] + nt.ar[i][2] * h[2];
        ok &= vabs(mc[i] - nx.centre[i]) <= nx.half[i] + mk[i] + gv;
      }
    }
    // The farther child first, so the nearer is on top; a child that failed is written but
    // not counted.
    const int far = key[0] >= key[1] ? 0 : 1;
    for (const int s : {far, 1 - far}) {
      NodePair& e = stack[n];
      e = cur;
      if (split_a) {
        e.x = s ? i1 : i0;
        for (int k = 0; k < 3; ++k) {
          e.x_centre_b[k] = mc[k][s];
          e.x_reach_b[k] = mk[k][s];
        }
      } else {
        e.y = s ? i1 : i0;
        for (int k = 0; k < 3; ++k) {
          e.y_centre_a[k] = mc[k][s];
          e.y_reach_a[k] = mk[k][s];
        }
      }
      n += ok[s] != 0;
    }
  }
  return false;
}

}  // namespace asimov::collision
