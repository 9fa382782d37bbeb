// Step 3 per pose [ours]: both bodies' halvings trees (voxel_grid.hpp) descended together, so
// only pairs of subtrees whose boxes meet are visited, down to voxel pairs. Header-only so the
// engine's voxel-pair visitor inlines.
#pragma once
#include "voxel_grid.hpp"

#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace asimov::collision {

// B's frame in A's for one pose, in float. A node of A's tree and one of B's are tested as two
// oriented boxes on their six face normals (A's axes, then B's), compared grown by `grow`: the
// pair's c + ε_r plus a bound on the float rounding of the mapping (32 float ulps of the
// magnitudes in play, and a few smallest normal floats for tiny scenes), so the test errs only
// toward "meet". A NaN (coordinates beyond float range) compares false and also means "meet".
//
// Each node also carries a slab (TreeSlabs): its faces lie in its box and within n . x in
// sm +- sr. Two more axes are tested per pair of nodes: the child's normal and the other node's.
// Along each, one node's extent is its slab, and the other's is bounded twice: by its box's
// projection, and by its own slab and box together (n' = alpha n + w with w = n' - alpha n, so
// n' . x lies within alpha (sm +- sr) plus w . x over the box), which is tight when the two
// normals are near parallel: two surfaces passing close without crossing. These sums carry more
// float rounding than the box test: `slab_grow` allows 512 float ulps of the magnitudes (each
// projection is a sum of at most a dozen products of terms up to twice the magnitude, and the
// float axes are within an ulp of the double rotation), on top of c + eps_r.
struct NodeTest {
  float r[3][3]{};   // B's axes in A's frame: a = r b + t
  float ar[3][3]{};  // |r|
  float t[3]{};
  float grow = 0;
  float slab_grow = 0;

  NodeTest() = default;
  // scale_a, scale_b: largest |local coordinate| of each body's container.
  NodeTest(const Pose& a_from_b, double grow_by, double scale_a, double scale_b) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        r[i][j] = static_cast<float>(a_from_b.linear()(i, j));
        ar[i][j] = std::fabs(r[i][j]);
      }
      t[i] = static_cast<float>(a_from_b.translation()[i]);
    }
    const double magnitude = a_from_b.translation().cwiseAbs().maxCoeff() + 2 * (scale_a + scale_b);
    const double g = grow_by + 32 * FLT_EPSILON * magnitude + 16 * FLT_MIN;
    grow = static_cast<float>(g);
    if (static_cast<double>(grow) < g) grow = std::nextafter(grow, INFINITY);
    const double sg = 1.001 * grow_by + 512 * FLT_EPSILON * magnitude + 64 * FLT_MIN;
    slab_grow = static_cast<float>(sg);
    if (static_cast<double>(slab_grow) < sg) slab_grow = std::nextafter(slab_grow, INFINITY);
  }
};

// A pair of nodes (x of A's tree, y of B's) whose boxes meet: refs (TreeNode::child), each
// box in its own frame, and what their test computed: y's centre and reach |r| hy in A's frame
// (the box of y in A's frame is within y_centre_a +- y_reach_a), x's likewise in B's frame.
struct NodePair {
  std::uint32_t x, y;
  float xc[3], xh[3], yc[3], yh[3];
  float y_centre_a[3], y_reach_a[3];
  float x_centre_b[3], x_reach_b[3];
  // Slabs (own frame): normal, middle, radius; whether each is worth testing (TreeNode::thin).
  // A node whose slab is not has its nearest ancestor's here (it holds the node's faces too).
  float xn[3], yn[3];
  float xm, xr, ym, yr;
  bool x_thin, y_thin;
};

namespace detail {

// Four lanes (the children of the node being split), GCC/Clang vector extensions: plain SSE on
// x86-64, no target flags.
using V4 = float __attribute__((vector_size(16)));
using M4 = std::int32_t __attribute__((vector_size(16)));
inline V4 load4(const std::array<float, 4>& a) {
  V4 v;
  std::memcpy(&v, a.data(), sizeof v);
  return v;
}
inline V4 vabs(V4 v) { return reinterpret_cast<V4>(reinterpret_cast<M4>(v) & 0x7fffffff); }

}  // namespace detail

// Depth first from the roots, splitting the node with the larger box; all children of the
// split node are tested at once (four lanes), those whose boxes do not meet the other node's
// are dropped and the rest visited nearest first. `leaf(va, vb, pair)` is called for every
// pair of non-empty voxels whose content boxes meet (a voxel pair) and returns true to stop (a
// contact); descend returns whether it stopped.
template <class Leaf>
bool descend(const VoxelGrid& ga, const VoxelGrid& gb, const NodeTest& nt, Leaf&& leaf) {
  using detail::M4;
  using detail::V4;
  using detail::vabs;
  if (ga.root == VoxelGrid::kNoRoot || gb.root == VoxelGrid::kNoRoot) return false;
  const float g = nt.grow;
  // Each step pops one pair and pushes at most four, one level (two halvings) deeper on one
  // side: at most 3 (depth A + depth B) + 1 entries.
  std::array<NodePair, 3 * (kMaxHalvings + 2) + 1> stack;
  {
    NodePair& e = stack[0];
    e.x = ga.root;
    e.y = gb.root;
    bool apart = false;
    for (int i = 0; i < 3; ++i) {
      e.xc[i] = ga.root_centre[static_cast<std::size_t>(i)];
      e.xh[i] = ga.root_half[static_cast<std::size_t>(i)];
      e.yc[i] = gb.root_centre[static_cast<std::size_t>(i)];
      e.yh[i] = gb.root_half[static_cast<std::size_t>(i)];
      e.xn[i] = ga.root_normal[static_cast<std::size_t>(i)];
      e.yn[i] = gb.root_normal[static_cast<std::size_t>(i)];
    }
    e.xm = ga.root_sm, e.xr = ga.root_sr, e.ym = gb.root_sm, e.yr = gb.root_sr;
    e.x_thin = ga.root_thin, e.y_thin = gb.root_thin;
    for (int i = 0; i < 3; ++i) {
      e.y_centre_a[i] = nt.t[i];
      e.y_reach_a[i] = 0;
      e.x_centre_b[i] = 0;
      e.x_reach_b[i] = 0;
      for (int j = 0; j < 3; ++j) {
        e.y_centre_a[i] += nt.r[i][j] * e.yc[j];
        e.y_reach_a[i] += nt.ar[i][j] * e.yh[j];
        e.x_centre_b[i] += nt.r[j][i] * (e.xc[j] - nt.t[j]);
        e.x_reach_b[i] += nt.ar[j][i] * e.xh[j];
      }
    }
    for (int i = 0; i < 3; ++i) {
      apart = apart || std::fabs(e.y_centre_a[i] - e.xc[i]) > e.xh[i] + e.y_reach_a[i] + g;
      apart = apart || std::fabs(e.yc[i] - e.x_centre_b[i]) > e.yh[i] + e.x_reach_b[i] + g;
    }
    if (apart) return false;
  }
  std::size_t n = 1;
  while (n > 0) {
    const NodePair cur = stack[--n];
    const bool x_leaf = (cur.x & TreeNode::kLeaf) != 0, y_leaf = (cur.y & TreeNode::kLeaf) != 0;
    if (x_leaf && y_leaf) {
      if (leaf(cur.x & ~TreeNode::kLeaf, cur.y & ~TreeNode::kLeaf, cur)) return true;
      continue;
    }
    const bool split_a =
        !x_leaf && (y_leaf || cur.xh[0] + cur.xh[1] + cur.xh[2] >= cur.yh[0] + cur.yh[1] + cur.yh[2]);
    const TreeNode& node = split_a ? ga.tree[cur.x] : gb.tree[cur.y];
    const V4 c[3] = {detail::load4(node.cx), detail::load4(node.cy), detail::load4(node.cz)};
    const V4 h[3] = {detail::load4(node.hx), detail::load4(node.hy), detail::load4(node.hz)};
    M4 apart = M4{0, 0, 0, 0};
    V4 key = V4{0, 0, 0, 0};
    V4 mc[3], mk[3];  // the children mapped into the other frame: centres, reaches
    if (split_a) {
      for (int i = 0; i < 3; ++i) {  // A's axes: y's centre and reach were mapped already
        const V4 d = cur.y_centre_a[i] - c[i];
        apart |= vabs(d) > h[i] + (cur.y_reach_a[i] + g);
        key += d * d;
      }
      const V4 q[3] = {c[0] - nt.t[0], c[1] - nt.t[1], c[2] - nt.t[2]};
      for (int j = 0; j < 3; ++j) {  // B's axes: the children mapped into B's frame
        mc[j] = nt.r[0][j] * q[0] + nt.r[1][j] * q[1] + nt.r[2][j] * q[2];
        mk[j] = nt.ar[0][j] * h[0] + nt.ar[1][j] * h[1] + nt.ar[2][j] * h[2];
        apart |= vabs(cur.yc[j] - mc[j]) > mk[j] + (cur.yh[j] + g);
      }
    } else {
      for (int j = 0; j < 3; ++j) {  // B's axes: x's centre and reach were mapped already
        const V4 e = c[j] - cur.x_centre_b[j];
        apart |= vabs(e) > h[j] + (cur.x_reach_b[j] + g);
        key += e * e;
      }
      for (int i = 0; i < 3; ++i) {  // A's axes: the children mapped into A's frame
        mc[i] = nt.r[i][0] * c[0] + nt.r[i][1] * c[1] + nt.r[i][2] * c[2] + nt.t[i];
        mk[i] = nt.ar[i][0] * h[0] + nt.ar[i][1] * h[1] + nt.ar[i][2] * h[2];
        apart |= vabs(mc[i] - cur.xc[i]) > mk[i] + (cur.xh[i] + g);
      }
    }
    const bool children_thin = node.thin != 0, other_thin = split_a ? cur.y_thin : cur.x_thin;
    const TreeSlabs& slabs = split_a ? ga.slabs[cur.x] : gb.slabs[cur.y];
    if (children_thin || other_thin) {
      // The slabs: the children's normals u (own frame) and the other node's normal (each only
      // when some slab along it is thin: wide slabs near the root would part nothing).
      const V4 u[3] = {detail::load4(slabs.nx), detail::load4(slabs.ny), detail::load4(slabs.nz)};
      const V4 sm = detail::load4(slabs.sm), sr = detail::load4(slabs.sr);
      // The other node in its own frame, and the maps between the frames: the other's point o
      // is a child-frame point r o + t (split A) or r^T (o - t) (split B).
      const float* oc = split_a ? cur.yc : cur.xc;
      const float* oh = split_a ? cur.yh : cur.xh;
      const float* on = split_a ? cur.yn : cur.xn;
      const float om = split_a ? cur.ym : cur.xm, orad = split_a ? cur.yr : cur.xr;
      V4 uo[3];  // u in the other's frame
      V4 off;    // u . x (child frame) = uo . o + off
      float v[3];  // the other's normal in the child frame; v . x = on . o + vt
      float vt;
      if (split_a) {
        for (int j = 0; j < 3; ++j) uo[j] = nt.r[0][j] * u[0] + nt.r[1][j] * u[1] + nt.r[2][j] * u[2];
        off = u[0] * nt.t[0] + u[1] * nt.t[1] + u[2] * nt.t[2];
        for (int i = 0; i < 3; ++i) v[i] = nt.r[i][0] * on[0] + nt.r[i][1] * on[1] + nt.r[i][2] * on[2];
        vt = v[0] * nt.t[0] + v[1] * nt.t[1] + v[2] * nt.t[2];
      } else {
        for (int i = 0; i < 3; ++i) uo[i] = nt.r[i][0] * u[0] + nt.r[i][1] * u[1] + nt.r[i][2] * u[2];
        off = -(uo[0] * nt.t[0] + uo[1] * nt.t[1] + uo[2] * nt.t[2]);
        for (int j = 0; j < 3; ++j) v[j] = nt.r[0][j] * on[0] + nt.r[1][j] * on[1] + nt.r[2][j] * on[2];
        vt = -(on[0] * nt.t[0] + on[1] * nt.t[1] + on[2] * nt.t[2]);
      }
      const float sg = nt.slab_grow;
      const V4 alpha = uo[0] * on[0] + uo[1] * on[1] + uo[2] * on[2];  // u . v
      const V4 aa = vabs(alpha);
      if (children_thin) {  // axis u: the child's slab against the other's box (and its slab and box)
        V4 c1 = off, r1 = V4{0, 0, 0, 0};
        for (int j = 0; j < 3; ++j) {
          c1 += uo[j] * oc[j];
          r1 += vabs(uo[j]) * oh[j];
        }
        apart |= vabs(sm - c1) > sr + r1 + sg;
        if (other_thin) {
          V4 c2 = alpha * om + off, r2 = aa * orad;
          for (int j = 0; j < 3; ++j) {
            const V4 w = uo[j] - alpha * on[j];
            c2 += w * oc[j];
            r2 += vabs(w) * oh[j];
          }
          apart |= vabs(sm - c2) > sr + r2 + sg;
        }
      }
      if (other_thin) {  // axis v: the other's slab against the children's boxes, then their slabs and boxes
        const float vm = om + vt;
        V4 d1 = V4{0, 0, 0, 0}, q1 = V4{0, 0, 0, 0}, d2 = alpha * sm, q2 = aa * sr;
        for (int k = 0; k < 3; ++k) {
          const V4 w = v[k] - alpha * u[k];
          d1 += v[k] * c[k];
          q1 += std::fabs(v[k]) * h[k];
          d2 += w * c[k];
          q2 += vabs(w) * h[k];
        }
        apart |= vabs(d1 - vm) > q1 + (orad + sg);
        apart |= vabs(d2 - vm) > q2 + (orad + sg);
      }
    }
    // Children that meet, farthest first so the nearest ends on top.
    // The live lanes as bits first (no branch per lane: which children meet is data-dependent
    // and mispredicted often), then only those are ordered.
    unsigned live = 0;
    for (int s = 0; s < 4; ++s)
      live |= static_cast<unsigned>((apart[s] == 0) & (node.child[static_cast<std::size_t>(s)] != TreeNode::kNone)) << s;
    int order[4];
    int m = 0;
    for (; live != 0; live &= live - 1) {
      const int s = __builtin_ctz(live);
      int k = m++;
      for (; k > 0 && key[order[k - 1]] < key[s]; --k) order[k] = order[k - 1];
      order[k] = s;
    }
    for (int o = 0; o < m; ++o) {
      const int s = order[o];
      const auto u = static_cast<std::size_t>(s);
      NodePair& e = stack[n++];
      e = cur;
      float* own_c = split_a ? e.xc : e.yc;
      float* own_h = split_a ? e.xh : e.yh;
      float* map_c = split_a ? e.x_centre_b : e.y_centre_a;
      float* map_k = split_a ? e.x_reach_b : e.y_reach_a;
      (split_a ? e.x : e.y) = node.child[u];
      own_c[0] = node.cx[u], own_c[1] = node.cy[u], own_c[2] = node.cz[u];
      own_h[0] = node.hx[u], own_h[1] = node.hy[u], own_h[2] = node.hz[u];
      const bool thin = ((node.thin >> s) & 1u) != 0;
      (split_a ? e.x_thin : e.y_thin) = thin;
      if (thin) {  // (a slab not worth testing is never read)
        float* own_n = split_a ? e.xn : e.yn;
        own_n[0] = slabs.nx[u], own_n[1] = slabs.ny[u], own_n[2] = slabs.nz[u];
        (split_a ? e.xm : e.ym) = slabs.sm[u];
        (split_a ? e.xr : e.yr) = slabs.sr[u];
      }
      for (int k = 0; k < 3; ++k) {
        map_c[k] = mc[k][s];
        map_k[k] = mk[k][s];
      }
    }
  }
  return false;
}

}  // namespace asimov::collision
