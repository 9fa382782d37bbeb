// Step 3: halvings, conservative face lists (checked by sampling), voxel classes, and the
// interference sub-matrices / voxel-pair buffer, the halvings tree and its descent.
#include "collision/src/containment.hpp"
#include "collision/src/interference.hpp"
#include "collision/src/tree_descent.hpp"
#include "collision/src/voxel_grid.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>
#include <set>

using namespace asimov::collision;

namespace {

// The voxel that holds local point p (floor of its scaled offset), or none.
bool voxel_of(const VoxelGrid& g, const Vec3& p, std::size_t& v) {
  int idx[3];
  for (int k = 0; k < 3; ++k) {
    const double s = (p[k] - g.container.origin[k]) / g.cell[k];
    if (s < 0 || s > g.cells[k]) return false;
    idx[k] = std::min(static_cast<int>(s), g.cells[k] - 1);
  }
  v = g.index(idx[0], idx[1], idx[2]);
  return true;
}

bool listed(const VoxelGrid& g, std::size_t v, std::uint32_t f) {
  const auto faces = g.faces_in(v);
  return std::find(faces.begin(), faces.end(), f) != faces.end();
}

}  // namespace

TEST_CASE("M halvings split the longest cells first, ties x, y, z", "[voxel_grid]") {
  CHECK(halve_cells(Vec3(1, 1, 1), 0) == std::array<int, 3>{1, 1, 1});
  CHECK(halve_cells(Vec3(1, 1, 1), 3) == std::array<int, 3>{2, 2, 2});
  CHECK(halve_cells(Vec3(1, 1, 1), 9) == std::array<int, 3>{8, 8, 8});
  CHECK(halve_cells(Vec3(8, 1, 1), 3) == std::array<int, 3>{8, 1, 1});
  CHECK(halve_cells(Vec3(4, 2, 1), 4) == std::array<int, 3>{8, 2, 1});  // 2,1,1 4,1,1 4,2,1 8,2,1
  CHECK(halve_cells(Vec3(4, 2, 1), 6) == std::array<int, 3>{8, 4, 2});
  const VoxelGrid g = build_voxel_grid(make_box(Vec3(10, 20, 40)), 9);
  CHECK(g.voxel_count() == 512);
  CHECK(g.offsets.size() == 513);
}

TEST_CASE("every face is listed in every voxel it touches (sampled)", "[voxel_grid]") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& [mesh, m] : {std::pair{test::make_merged_part(), 9}, std::pair{make_cylinder(10, 30, 20), 7},
                                std::pair{make_box(Vec3(3, 5, 7)), 6}}) {
    const VoxelGrid g = build_voxel_grid(mesh, m);
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
      const Triangle& t = mesh.triangles[f];
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      for (int s = 0; s < 400; ++s) {
        double x = u(rng), y = u(rng);
        if (x + y > 1) {
          x = 1 - x;
          y = 1 - y;
        }
        // Include the vertices and edges, where voxel boundaries are hit exactly.
        if (s < 3) x = s == 1, y = s == 2;
        const Vec3 p = a + x * (b - a) + y * (c - a);
        std::size_t v = 0;
        REQUIRE(voxel_of(g, p, v));
        REQUIRE(listed(g, v, f));
      }
    }
    // Lists are sorted by face and every listed face really is near its voxel.
    for (std::size_t v = 0; v < g.voxel_count(); ++v) {
      const auto faces = g.faces_in(v);
      REQUIRE(std::is_sorted(faces.begin(), faces.end()));
    }
  }
}

TEST_CASE("the triangle-box test finds a triangle inside one voxel (the thesis's test would not)", "[voxel_grid]") {
  const TriangleVerts t{Vec3(0.1, 0.1, 0.1), Vec3(0.2, 0.1, 0.1), Vec3(0.1, 0.2, 0.1)};
  CHECK(triangle_box_overlap(Vec3(0, 0, 0), Vec3(1, 1, 1), t));
  CHECK_FALSE(triangle_box_overlap(Vec3(5, 0, 0), Vec3(1, 1, 1), t));
  // A big triangle crossing a small box without any vertex inside.
  CHECK(triangle_box_overlap(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1), {Vec3(-10, -10, 0), Vec3(10, -10, 0), Vec3(0, 10, 0)}));
  // Plane passes near the box corner but misses it.
  CHECK_FALSE(triangle_box_overlap(Vec3(0, 0, 0), Vec3(1, 1, 1), {Vec3(3.1, 0, 0), Vec3(0, 3.1, 0), Vec3(0, 0, 3.1)}));
  CHECK(triangle_box_overlap(Vec3(0, 0, 0), Vec3(1, 1, 1), {Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3)}));  // touches corner
}

TEST_CASE("voxel classes: surface, flood-filled outside, inside components", "[voxel_grid]") {
  const Polyhedron box = make_box(Vec3(10, 10, 10));
  const VoxelGrid g = build_voxel_grid(box, 9);  // 8^3: the two central layers are inside
  REQUIRE(g.classes.size() == 512);
  int inside = 0, surface = 0;
  for (std::size_t v = 0; v < 512; ++v) {
    inside += g.classes[v] == VoxelClass::inside;
    surface += g.classes[v] == VoxelClass::surface;
    CHECK((g.classes[v] == VoxelClass::surface) == !g.voxel_empty(v));
  }
  CHECK(inside == 6 * 6 * 6);
  CHECK(surface == 512 - 216);
  // The L prism has empty voxels outside in its notch (reached from the border).
  const VoxelGrid l = build_voxel_grid(test::make_l_prism(40, 10, 20), 9);
  int outside = 0;
  for (const VoxelClass c : l.classes) outside += c == VoxelClass::outside;
  CHECK(outside > 0);
  // An open mesh has no classes.
  Polyhedron open = box;
  open.triangles.pop_back();
  CHECK(build_voxel_grid(open, 6).classes.empty());
}

TEST_CASE("exact point-in-solid: inside, outside, on the surface", "[containment]") {
  const Polyhedron box = make_box(Vec3(2, 2, 2));
  CHECK(point_in_solid(Vec3(0, 0, 0), box.vertices, box.triangles) == PointClass::inside);
  CHECK(point_in_solid(Vec3(0.999, 0.999, -0.999), box.vertices, box.triangles) == PointClass::inside);
  CHECK(point_in_solid(Vec3(1.001, 0, 0), box.vertices, box.triangles) == PointClass::outside);
  CHECK(point_in_solid(Vec3(1, 0.3, 0.2), box.vertices, box.triangles) == PointClass::on_surface);
  CHECK(point_in_solid(Vec3(1, 1, 1), box.vertices, box.triangles) == PointClass::on_surface);
  const Polyhedron l = test::make_l_prism(40, 10, 20);
  CHECK(point_in_solid(Vec3(5, 5, 10), l.vertices, l.triangles) == PointClass::inside);
  CHECK(point_in_solid(Vec3(30, 30, 10), l.vertices, l.triangles) == PointClass::outside);  // the notch
  CHECK(point_in_solid(Vec3(10, 10, 10), l.vertices, l.triangles) == PointClass::on_surface);  // reflex edge
}

TEST_CASE("interference sub-matrices and voxel pairs cover every pair of overlapping voxels", "[voxel_grid]") {
  // Brute force: vB's eight corners mapped into A's frame give a box; every non-empty vA that
  // this box overlaps (by more than a small slack) must be paired with vB in the buffer, if vB
  // is in B's sub-matrix (overlaps A's container box in B's frame).
  std::mt19937_64 rng(5);
  const VoxelGrid ga = build_voxel_grid(test::make_merged_part(), 6);
  const VoxelGrid gb = build_voxel_grid(make_cylinder(12, 40, 12), 5);
  std::vector<VoxelPair> pairs;
  int nonempty_runs = 0;
  for (int n = 0; n < 300; ++n) {
    const Pose pa = test::random_pose(rng, 20), pb = test::random_pose(rng, 20);
    const double grow = 0.25 * (n % 3);
    collect_voxel_pairs(ga, pa, gb, pb, grow, pairs);
    std::set<std::pair<std::uint32_t, std::uint32_t>> got;
    for (const VoxelPair& p : pairs) {
      REQUIRE(!ga.voxel_empty(p.a));
      REQUIRE(!gb.voxel_empty(p.b));
      REQUIRE(got.emplace(p.a, p.b).second);  // no duplicates
    }
    nonempty_runs += !pairs.empty();
    const Pose a_from_b = pa.inverse(Eigen::Isometry) * pb;
    const Box a_in_b = minimax_box(ga.container, pb.inverse(Eigen::Isometry) * pa);
    for (int kb = 0; kb < gb.cells[2]; ++kb)
      for (int jb = 0; jb < gb.cells[1]; ++jb)
        for (int ib = 0; ib < gb.cells[0]; ++ib) {
          const std::size_t vb = gb.index(ib, jb, kb);
          if (gb.voxel_empty(vb)) continue;
          const Box bb = gb.voxel_box(ib, jb, kb);
          if (separated(bb, a_in_b, grow - 1e-9)) continue;
          Box m{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
          for (int c = 0; c < 8; ++c) {
            const Vec3 corner((c & 1) ? bb.hi.x() : bb.lo.x(), (c & 2) ? bb.hi.y() : bb.lo.y(), (c & 4) ? bb.hi.z() : bb.lo.z());
            const Vec3 q = a_from_b * corner;
            m.lo = m.lo.cwiseMin(q);
            m.hi = m.hi.cwiseMax(q);
          }
          for (int ka = 0; ka < ga.cells[2]; ++ka)
            for (int ja = 0; ja < ga.cells[1]; ++ja)
              for (int ia = 0; ia < ga.cells[0]; ++ia) {
                const std::size_t va = ga.index(ia, ja, ka);
                if (ga.voxel_empty(va)) continue;
                const Box ab = ga.voxel_box(ia, ja, ka);
                if (!separated(ab, m, grow - 1e-9))
                  REQUIRE(got.count({static_cast<std::uint32_t>(va), static_cast<std::uint32_t>(vb)}) == 1);
              }
        }
  }
  CHECK(nonempty_runs > 30);
}

namespace {

// Leaves of the halvings tree under ref (voxel indices), depth first.
void tree_leaves(const VoxelGrid& g, std::uint32_t ref, std::vector<std::uint32_t>& out) {
  if (ref & TreeNode::kLeaf) {
    out.push_back(ref & ~TreeNode::kLeaf);
    return;
  }
  for (const std::uint32_t c : g.tree[ref].child)
    if (c != TreeNode::kNone) tree_leaves(g, c, out);
}

// Exact in double: do content boxes x (A's frame) and y (B's frame, placed by a_from_b) meet
// within `grow` on all six face normals?
bool boxes_meet(const Box& x, const Box& y, const Pose& a_from_b, double grow) {
  const Vec3 xc = 0.5 * (x.lo + x.hi), xh = 0.5 * (x.hi - x.lo);
  const Vec3 yc = 0.5 * (y.lo + y.hi), yh = 0.5 * (y.hi - y.lo);
  const Mat3 r = a_from_b.linear(), ar = r.cwiseAbs();
  const Vec3 d = a_from_b * yc - xc;
  for (int i = 0; i < 3; ++i)
    if (std::fabs(d[i]) > xh[i] + ar.row(i).dot(yh) + grow) return false;
  const Vec3 e = r.transpose() * d;
  for (int j = 0; j < 3; ++j)
    if (std::fabs(e[j]) > ar.col(j).dot(xh) + yh[j] + grow) return false;
  return true;
}

// A node's slab (TreeNode): normal, middle, radius.
struct SlabOf {
  Vec3 n;
  double m, r;
};
// Per voxel, the boxes and slabs of the nodes from the root down to it (lanes: float boxes).
using Chain = std::vector<std::pair<Box, SlabOf>>;
void chains(const VoxelGrid& g, std::uint32_t ref, Chain& path, std::map<std::uint32_t, Chain>& out) {
  if (ref & TreeNode::kLeaf) {
    out[ref & ~TreeNode::kLeaf] = path;
    return;
  }
  const TreeNode& n = g.tree[ref];
  const TreeSlabs& l = g.slabs[ref];
  for (std::size_t s = 0; s < 4; ++s) {
    if (n.child[s] == TreeNode::kNone) continue;
    const Vec3 c(n.cx[s], n.cy[s], n.cz[s]), h(n.hx[s], n.hy[s], n.hz[s]);
    path.push_back({Box{c - h, c + h}, SlabOf{Vec3(l.nx[s], l.ny[s], l.nz[s]), l.sm[s], l.sr[s]}});
    chains(g, n.child[s], path, out);
    path.pop_back();
  }
}
std::map<std::uint32_t, Chain> chains(const VoxelGrid& g) {
  const Vec3 c(g.root_centre[0], g.root_centre[1], g.root_centre[2]), h(g.root_half[0], g.root_half[1], g.root_half[2]);
  Chain path{{Box{c - h, c + h}, SlabOf{Vec3(g.root_normal[0], g.root_normal[1], g.root_normal[2]), g.root_sm, g.root_sr}}};
  std::map<std::uint32_t, Chain> out;
  chains(g, g.root, path, out);
  return out;
}

// Exact in double: are content box x within slab sx (A's frame) and content box y within slab sy
// (B's frame, placed by a_from_b) apart by more than `grow` along either normal? The same bounds
// as the descent's (tree_descent.hpp): along one normal, the other's extent is bounded by its
// box and by its slab and box together.
bool slabs_apart(const Box& x, const SlabOf& sx, const Box& y, const SlabOf& sy, const Pose& a_from_b, double grow) {
  const Vec3 xc = 0.5 * (x.lo + x.hi), xh = 0.5 * (x.hi - x.lo);
  const Vec3 yc = 0.5 * (y.lo + y.hi), yh = 0.5 * (y.hi - y.lo);
  const Mat3 r = a_from_b.linear();
  const Vec3 t = a_from_b.translation();
  const Vec3 ny = r * sy.n;  // B's normal in A's frame; ny . a = sy.n . b + ny . t
  const double alpha = sx.n.dot(ny);
  // B's extent along a direction u of A's frame: its box, and its slab with its box.
  const auto b_along = [&](const Vec3& u, double lo_hi[2][2]) {
    const Vec3 ub = r.transpose() * u, w = ub - alpha * sy.n;
    const double off = u.dot(t);
    const double c1 = ub.dot(yc) + off, r1 = ub.cwiseAbs().dot(yh);
    const double c2 = alpha * sy.m + w.dot(yc) + off, r2 = std::fabs(alpha) * sy.r + w.cwiseAbs().dot(yh);
    lo_hi[0][0] = c1 - r1, lo_hi[0][1] = c1 + r1, lo_hi[1][0] = c2 - r2, lo_hi[1][1] = c2 + r2;
  };
  double bx[2][2];
  b_along(sx.n, bx);
  for (const auto& i : bx)
    if (sx.m - sx.r > i[1] + grow || i[0] > sx.m + sx.r + grow) return true;
  // A's extent along ny: its box, and its slab with its box; B's: its slab.
  const Vec3 w = ny - alpha * sx.n;
  const double bm = sy.m + ny.dot(t);
  const double c1 = ny.dot(xc), r1 = ny.cwiseAbs().dot(xh);
  const double c2 = alpha * sx.m + w.dot(xc), r2 = std::fabs(alpha) * sx.r + w.cwiseAbs().dot(xh);
  return std::fabs(c1 - bm) > r1 + sy.r + grow || std::fabs(c2 - bm) > r2 + sy.r + grow;
}

}  // namespace

TEST_CASE("every slab of the halvings tree holds the faces below it", "[voxel_grid]") {
  // Each node's slab (TreeNode: its normal, and n . x within sm +- sr) must hold every point of
  // the faces listed in the voxels below it that lies in their content boxes, as measured (small
  // nodes) or as composed from its children's slabs (large ones); also far from the origin and
  // at small and large scales.
  Pose far = Pose::Identity();
  far.translation() = Vec3(1e5, -3e4, 2e4);
  for (const auto& [mesh, m] :
       {std::pair{test::make_merged_part(), 6}, std::pair{make_cylinder(12, 40, 12), 9},
        std::pair{transformed(make_cylinder(12, 40, 48), far), 12}, std::pair{test::make_l_prism(40, 10, 20), 3},
        std::pair{make_box(Vec3(1, 1, 1)), 0}, std::pair{make_box(Vec3(1e-3, 2e-3, 1e-3)), 4},
        std::pair{make_cylinder(1e3, 4e3, 64), 11}}) {
    const VoxelGrid g = build_voxel_grid(mesh, m);
    REQUIRE(g.root != VoxelGrid::kNoRoot);
    // The points of each face below the node that lie in its voxels' content boxes (the parts
    // step 4 looks at; a face may reach far beyond): vertices, and 66 points spread over it.
    int checked = 0;
    // Captured by name: clang before 16 cannot capture a structured binding.
    const auto holds = [&, &mesh = mesh, m = m](std::uint32_t ref, const Vec3& n, double mid, double radius) {
      std::vector<std::uint32_t> below;
      tree_leaves(g, ref, below);
      for (const std::uint32_t v : below)
        for (const std::uint32_t f : g.faces_in(v)) {
          const Triangle& t = mesh.triangles[f];
          for (int i = 0; i <= 10; ++i)
            for (int j = 0; i + j <= 10; ++j) {
              const Vec3 p = (i * mesh.vertices[t[0]] + j * mesh.vertices[t[1]] + (10 - i - j) * mesh.vertices[t[2]]) / 10;
              const Box& b = g.content[v];
              if ((p.array() < b.lo.array()).any() || (p.array() > b.hi.array()).any()) continue;
              const double d = n.dot(p);
              ++checked;
              INFO("faces " << mesh.triangles.size() << ", M " << m << ", point " << p.transpose());
              REQUIRE(d >= mid - radius);
              REQUIRE(d <= mid + radius);
            }
        }
    };
    holds(g.root, Vec3(g.root_normal[0], g.root_normal[1], g.root_normal[2]), g.root_sm, g.root_sr);
    REQUIRE(g.slabs.size() == g.tree.size());
    for (std::size_t i = 0; i < g.tree.size(); ++i)
      for (std::size_t s = 0; s < 4; ++s) {
        const TreeSlabs& l = g.slabs[i];
        if (g.tree[i].child[s] != TreeNode::kNone) holds(g.tree[i].child[s], Vec3(l.nx[s], l.ny[s], l.nz[s]), l.sm[s], l.sr[s]);
      }
    CHECK(checked > 500);
  }
}

TEST_CASE("the halvings tree has every non-empty voxel as one leaf, boxes holding its content", "[voxel_grid]") {
  for (const auto& [mesh, m] : {std::pair{test::make_merged_part(), 6}, std::pair{make_cylinder(12, 40, 12), 9},
                                std::pair{test::make_l_prism(40, 10, 20), 3}, std::pair{make_box(Vec3(1, 1, 1)), 0}}) {
    const VoxelGrid g = build_voxel_grid(mesh, m);
    REQUIRE(g.root != VoxelGrid::kNoRoot);
    std::vector<std::uint32_t> leaves;
    tree_leaves(g, g.root, leaves);
    std::vector<std::uint32_t> nonempty;
    for (std::uint32_t v = 0; v < g.voxel_count(); ++v)
      if (!g.voxel_empty(v)) nonempty.push_back(v);
    std::sort(leaves.begin(), leaves.end());
    CHECK(leaves == nonempty);
    // Every node lane's float box holds the content boxes of the voxels below it.
    for (const TreeNode& n : g.tree)
      for (std::size_t s = 0; s < 4; ++s) {
        if (n.child[s] == TreeNode::kNone) continue;
        std::vector<std::uint32_t> below;
        tree_leaves(g, n.child[s], below);
        const Vec3 c(n.cx[s], n.cy[s], n.cz[s]), h(n.hx[s], n.hy[s], n.hz[s]);
        for (const std::uint32_t v : below)
          for (int k = 0; k < 3; ++k) {
            REQUIRE(g.content[v].lo[k] >= c[k] - h[k]);
            REQUIRE(g.content[v].hi[k] <= c[k] + h[k]);
          }
      }
  }
}

TEST_CASE("the tree descent visits every voxel pair whose content boxes and slabs meet, and stops when asked", "[voxel_grid]") {
  // The reference is exact in double (boxes_meet, slabs_apart on every pair of the two voxels'
  // ancestors); the descent's float arithmetic errs only toward "meet". Also counted: the voxel pairs the slabs part (boxes meeting), so the
  // slab test is seen to do something.
  std::mt19937_64 rng(8);
  const VoxelGrid ga = build_voxel_grid(test::make_merged_part(), 7);
  const VoxelGrid gb = build_voxel_grid(make_cylinder(12, 40, 12), 6);
  const auto ca = chains(ga), cb = chains(gb);
  int with_pairs = 0, parted = 0;
  for (int n = 0; n < 300; ++n) {
    const Pose a_from_b = test::random_pose(rng, 25);
    const double grow = 0.25 * (n % 3);
    const NodeTest nt(a_from_b, grow, ga.container.scale, gb.container.scale);
    std::set<std::pair<std::uint32_t, std::uint32_t>> got;
    descend(ga, gb, nt, [&](std::uint32_t va, std::uint32_t vb, const NodePair&) {
      REQUIRE(got.emplace(va, vb).second);  // each voxel pair once
      return false;
    });
    with_pairs += !got.empty();
    for (std::uint32_t va = 0; va < ga.voxel_count(); ++va) {
      if (ga.voxel_empty(va)) continue;
      for (std::uint32_t vb = 0; vb < gb.voxel_count(); ++vb)
        if (!gb.voxel_empty(vb) && boxes_meet(ga.content[va], gb.content[vb], a_from_b, grow)) {
          // The descent tests pairs of the voxels' ancestors (or themselves): apart there, the
          // faces below are apart.
          bool apart = false;
          for (const auto& [bx, sx] : ca.at(va))
            for (const auto& [by, sy] : cb.at(vb)) apart = apart || slabs_apart(bx, sx, by, sy, a_from_b, grow);
          if (apart) {
            parted += got.count({va, vb}) == 0;
            continue;
          }
          REQUIRE(got.count({va, vb}) == 1);
        }
    }
    if (got.size() > 1) {  // the first voxel pair that asks to stop ends the descent
      int calls = 0;
      CHECK(descend(ga, gb, nt, [&](std::uint32_t, std::uint32_t, const NodePair&) { return ++calls == 2; }));
      CHECK(calls == 2);
    }
  }
  CHECK(with_pairs > 30);
  CHECK(parted > 100);
}

TEST_CASE("the grid's triangle-box test accepts whatever the one-box test accepts", "[voxel_grid]") {
  // TriangleBoxTest (the voxelisation's, with its axes computed once per triangle) against
  // triangle_box_overlap on random triangles and boxes of one size: never a box rejected that
  // the reference accepts, and no more than a rare extra one (rounding room only).
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-10, 10);
  const Vec3 half(1.5, 0.75, 2.0);
  int agree = 0, extra = 0, lost = 0;
  for (int n = 0; n < 2000; ++n) {
    const TriangleVerts t{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
    const TriangleBoxTest test(t, half, 20);
    for (int k = 0; k < 50; ++k) {
      const Vec3 c(u(rng), u(rng), u(rng));
      const bool ref = triangle_box_overlap(c, half, t), fast = test.overlaps(c);
      agree += ref == fast;
      extra += fast && !ref;
      lost += ref && !fast;
    }
  }
  CHECK(lost == 0);
  CHECK(extra <= 2);
  CHECK(agree >= 100000 - 2);
}
