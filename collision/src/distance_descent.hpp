// Distance query, step 3 [ours]: branch and bound over both bodies' halvings trees
// (voxel_grid.hpp), in double. A pair of nodes is dropped when a lower bound on the distance
// between their boxes is not below the best distance found so far (or the cut-off); children
// are expanded nearest first. Header-only so the engine's leaf visitor inlines.
#pragma once
#include "voxel_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace asimov::collision {

// B's frame in A's for one pose (a = r b + t), and the lower bound of two node boxes.
struct DistanceNodeTest {
  Mat3 r, ar;   // rotation and |rotation|
  Vec3 t;
  double slack; // subtracted from every bound: the rounding of mapping boxes (eps_r of the pair)

  DistanceNodeTest(const Pose& a_from_b, double slack_mm)
      : r(a_from_b.linear()), ar(a_from_b.linear().cwiseAbs()), t(a_from_b.translation()), slack(slack_mm) {}

  // Boxes x (A's frame) and y (B's frame) as centre and half sides. Each is mapped into the
  // other's frame as the axis-aligned box holding it (centre R c + t, half |R| h); the distance
  // of two axis-aligned boxes is a lower bound on the distance of anything inside them, so the
  // larger of the two frames' values is one too.
  double lower_bound(const Vec3& xc, const Vec3& xh, const Vec3& yc, const Vec3& yh) const {
    const Vec3 yca = r * yc + t, yra = ar * yh;
    const Vec3 xcb = r.transpose() * (xc - t), xrb = ar.transpose() * xh;
    double s1 = 0, s2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double g1 = std::fabs(yca[k] - xc[k]) - xh[k] - yra[k];
      const double g2 = std::fabs(xcb[k] - yc[k]) - yh[k] - xrb[k];
      s1 += g1 > 0 ? g1 * g1 : 0.0;
      s2 += g2 > 0 ? g2 * g2 : 0.0;
    }
    return std::sqrt(s1 > s2 ? s1 : s2) - slack;
  }
};

// A pair of nodes waiting in the distance descent: refs, boxes, and their lower bound.
struct DistanceEntry {
  std::uint32_t x, y;
  Vec3 xc, xh, yc, yh;
  double lb;
};

// Best first from the roots: the pair with the smallest bound is expanded next (a heap in
// `heap`, reused between queries), splitting the node with the larger box, so only node pairs
// whose bound is below the final distance are ever expanded. `leaf(va, vb)` is called for every
// pair of non-empty voxels whose bound is below `best` (which it may lower).
template <class Leaf>
void descend_distance(const VoxelGrid& ga, const VoxelGrid& gb, const DistanceNodeTest& nt, const double& best,
                      std::vector<DistanceEntry>& heap, Leaf&& leaf) {
  heap.clear();
  if (ga.root == VoxelGrid::kNoRoot || gb.root == VoxelGrid::kNoRoot) return;
  auto vec = [](const std::array<float, 3>& a) { return Vec3(a[0], a[1], a[2]); };
  auto farther = [](const DistanceEntry& p, const DistanceEntry& q) { return p.lb > q.lb; };
  DistanceEntry root{ga.root, gb.root, vec(ga.root_centre), vec(ga.root_half), vec(gb.root_centre), vec(gb.root_half), 0};
  root.lb = nt.lower_bound(root.xc, root.xh, root.yc, root.yh);
  if (!(root.lb < best)) return;
  heap.push_back(root);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), farther);
    const DistanceEntry cur = heap.back();
    heap.pop_back();
    if (!(cur.lb < best)) return;  // the smallest bound left: nothing nearer remains
    const bool x_leaf = (cur.x & TreeNode::kLeaf) != 0, y_leaf = (cur.y & TreeNode::kLeaf) != 0;
    if (x_leaf && y_leaf) {
      leaf(cur.x & ~TreeNode::kLeaf, cur.y & ~TreeNode::kLeaf);
      continue;
    }
    const bool split_a = !x_leaf && (y_leaf || cur.xh.sum() >= cur.yh.sum());
    const TreeNode& node = split_a ? ga.tree[cur.x] : gb.tree[cur.y];
    for (std::size_t s = 0; s < 4; ++s) {
      if (node.child[s] == TreeNode::kNone) continue;
      DistanceEntry e = cur;
      const Vec3 c(node.cx[s], node.cy[s], node.cz[s]), h(node.hx[s], node.hy[s], node.hz[s]);
      if (split_a) {
        e.x = node.child[s], e.xc = c, e.xh = h;
      } else {
        e.y = node.child[s], e.yc = c, e.yh = h;
      }
      e.lb = nt.lower_bound(e.xc, e.xh, e.yc, e.yh);
      if (!(e.lb < best)) continue;
      heap.push_back(e);
      std::push_heap(heap.begin(), heap.end(), farther);
    }
  }
}

}  // namespace asimov::collision
