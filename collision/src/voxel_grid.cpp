#include "voxel_grid.hpp"

#include "containment.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <cfloat>
#include <cmath>
#include <span>
#include <utility>

namespace asimov::collision {
namespace {

int clamp_index(double x, int n) {
  if (!(x > 0)) return 0;  // also NaN
  if (x >= n - 1) return n - 1;
  return static_cast<int>(std::floor(x));
}

// cell_range, inlined into the voxelisation's loops (two calls per face).
inline CellRange range_of(const VoxelGrid& g, const Box& b) {
  CellRange r;
  for (int k = 0; k < 3; ++k) {
    const double o = g.container.origin[k];
    if (b.hi[k] < o || b.lo[k] > o + g.container.size[k] || !(b.lo[k] <= b.hi[k])) return CellRange{};
    // A product instead of the quotient: off by an ulp at most, far inside the margins every
    // caller grows its box by (so still conservative).
    r.lo[k] = clamp_index((b.lo[k] - o) * g.inv_cell[k], g.cells[k]);
    r.hi[k] = clamp_index((b.hi[k] - o) * g.inv_cell[k], g.cells[k]);
  }
  return r;
}

// Empty voxels reachable from the grid border through empty faces are outside; every other
// empty component is on one side of the surface, decided by one exact point-in-solid test.
void classify_voxels(VoxelGrid& g, const Polyhedron& mesh) {
  constexpr auto unknown = static_cast<VoxelClass>(255);
  const std::size_t n = g.voxel_count();
  g.classes.assign(n, unknown);
  for (std::size_t v = 0; v < n; ++v)
    if (!g.voxel_empty(v)) g.classes[v] = VoxelClass::surface;
  std::vector<std::size_t> stack;
  auto fill = [&](std::size_t seed, VoxelClass c) {
    g.classes[seed] = c;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      const int i = static_cast<int>(v % g.cells[0]);
      const int j = static_cast<int>((v / g.cells[0]) % g.cells[1]);
      const int k = static_cast<int>(v / (static_cast<std::size_t>(g.cells[0]) * g.cells[1]));
      const std::array<std::array<int, 3>, 6> nb{{{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                                                  {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= g.cells[0] || q[1] >= g.cells[1] || q[2] >= g.cells[2]) continue;
        const std::size_t w = g.index(q[0], q[1], q[2]);
        if (g.classes[w] != unknown) continue;
        g.classes[w] = c;
        stack.push_back(w);
      }
    }
  };
  for (int k = 0; k < g.cells[2]; ++k)
    for (int j = 0; j < g.cells[1]; ++j)
      for (int i = 0; i < g.cells[0]; ++i) {
        const bool border = i == 0 || j == 0 || k == 0 || i == g.cells[0] - 1 || j == g.cells[1] - 1 || k == g.cells[2] - 1;
        if (border && g.classes[g.index(i, j, k)] == unknown) fill(g.index(i, j, k), VoxelClass::outside);
      }
  for (int k = 0; k < g.cells[2]; ++k)
    for (int j = 0; j < g.cells[1]; ++j)
      for (int i = 0; i < g.cells[0]; ++i) {
        if (g.classes[g.index(i, j, k)] != unknown) continue;
        const Box b = g.voxel_box(i, j, k);
        const PointClass pc = point_in_solid(0.5 * (b.lo + b.hi), mesh.vertices, mesh.triangles);
        // on_surface cannot happen (no face touches an empty voxel); keep it conservative.
        fill(g.index(i, j, k), pc == PointClass::inside ? VoxelClass::inside
                               : pc == PointClass::outside ? VoxelClass::outside
                                                           : VoxelClass::surface);
      }
}

// The axis each of the M halvings doubles, in order (halve_cells' choices).
std::vector<int> halving_axes(const Vec3& size, int halvings) {
  std::vector<int> axes;
  std::array<int, 3> n{1, 1, 1};
  for (int m = 0; m < halvings; ++m) {
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (size[k] / n[k] > size[axis] / n[axis]) axis = k;
    n[static_cast<std::size_t>(axis)] *= 2;
    axes.push_back(axis);
  }
  return axes;
}

// A node's slab (TreeNode) while the tree is built, in double: the sum of its faces' normals
// (area-weighted: the cross products, over every listing of a face in its voxels), the normal
// as it will be stored (rounded to float, then used as given: any direction bounds the faces)
// and n . x over the faces' vertices, within the box's projection.
struct Slab {
  Vec3 sum = Vec3::Zero();
  Vec3 n = Vec3::UnitX();
  double lo = 0, hi = 0;
};

// The binary halvings tree as built.
struct BinaryNode {
  Box box;
  Slab slab;
  std::uint32_t second = 0;  // index of the second child (the first is next); 0 for a leaf
  std::uint32_t voxel = 0;   // leaf: its voxel index
  bool leaf() const { return second == 0; }
};

// Up to this many face listings a node's slab is measured on its faces' vertices; above, it is
// bounded from its two children's slabs (cheaper, looser; the upper levels' normals spread
// anyway).
constexpr std::uint32_t kSlabExactListings = 256;

// x rounded to float, the result opaque to the optimiser: GCC 12 at -O3 folds (double)(float)x
// to x when it vectorises two such conversions (measured here: slabs measured along the
// unrounded normal while the rounded one was stored, a bound off by 1e-7 relative).
float opaque_float(double x) {
  float f = static_cast<float>(x);
  asm volatile("" : "+m"(f));
  return f;
}

// The stored normal: the direction of `sum` rounded to float (x when the normals cancel).
Vec3 slab_normal(const Vec3& sum) {
  const double len = sum.norm();
  if (!(len > 0) || !std::isfinite(len)) return Vec3::UnitX();
  const Vec3 u = sum / len;
  return Vec3(opaque_float(u.x()), opaque_float(u.y()), opaque_float(u.z()));
}

// [lo, hi] of n . x over the box (centre +- half).
std::pair<double, double> box_along(const Vec3& n, const Box& b) {
  const Vec3 c = 0.5 * (b.lo + b.hi), h = 0.5 * (b.hi - b.lo);
  const double m = n.dot(c), r = std::abs(n.x()) * h.x() + std::abs(n.y()) * h.y() + std::abs(n.z()) * h.z();
  return {m - r, m + r};
}

// The slab's interval cut to the box's projection, widened by the rounding of the dot products
// (a relative 1e-12 of the magnitudes in play: far above their few ulps).
void finish_slab(Slab& s, const Box& box, double magnitude) {
  const auto [blo, bhi] = box_along(s.n, box);
  const double room = 1e-12 * magnitude;
  double lo = std::max(s.lo, blo), hi = std::min(s.hi, bhi);
  if (!(lo <= hi)) lo = s.lo, hi = s.hi;  // cannot happen (the faces' parts lie in the box); keep it sound
  s.lo = lo - room;
  s.hi = hi + room;
}

// A leaf's or a small node's slab, measured on the faces listed in `voxels`.
Slab measured_slab(const VoxelGrid& g, const Polyhedron& mesh, std::span<const std::uint32_t> voxels, const Box& box,
                   double magnitude) {
  Slab s;
  for (const std::uint32_t v : voxels)
    for (const std::uint32_t f : g.faces_in(v)) {
      const Triangle& t = mesh.triangles[f];
      const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
      s.sum += (q - p).cross(r - p);
    }
  s.n = slab_normal(s.sum);
  s.lo = INFINITY;
  s.hi = -INFINITY;
  for (const std::uint32_t v : voxels)
    for (const std::uint32_t f : g.faces_in(v))
      for (const std::uint32_t i : mesh.triangles[f]) {
        const double d = s.n.dot(mesh.vertices[i]);
        s.lo = std::min(s.lo, d);
        s.hi = std::max(s.hi, d);
      }
  finish_slab(s, box, magnitude);
  return s;
}

// A node's slab from its children's: along n, each child's faces lie in its box and in its slab,
// so within alpha [lo_c, hi_c] + w . x over its box, where alpha = n . n_c and w = n - alpha n_c.
Slab composed_slab(const BinaryNode& a, const BinaryNode& b, const Box& box, double magnitude) {
  Slab s;
  s.sum = a.slab.sum + b.slab.sum;
  s.n = slab_normal(s.sum);
  s.lo = INFINITY;
  s.hi = -INFINITY;
  for (const BinaryNode* c : {&a, &b}) {
    const double alpha = s.n.dot(c->slab.n);
    const auto [wlo, whi] = box_along(s.n - alpha * c->slab.n, c->box);
    const auto [blo, bhi] = box_along(s.n, c->box);
    const double x = alpha * c->slab.lo, y = alpha * c->slab.hi;
    s.lo = std::min(s.lo, std::max(blo, std::min(x, y) + wlo));
    s.hi = std::max(s.hi, std::min(bhi, std::max(x, y) + whi));
  }
  finish_slab(s, box, magnitude);
  return s;
}

// Appends the subtree of the cell `r` (after `depth` halvings) in preorder and returns its
// box; nothing when the cell holds no non-empty voxel. A cell with one non-empty half is
// replaced by that half's subtree (same box), so every inner node has two children.
// `leaves`: the voxels of the subtree are appended (for the slabs of small nodes).
struct TreeBuild {
  const VoxelGrid& g;
  const Polyhedron& mesh;
  const std::vector<int>& axes;
  double magnitude;
  std::vector<BinaryNode> tree;
  std::vector<std::uint32_t> leaves;
};

bool add_subtree(TreeBuild& b, const CellRange& r, std::size_t depth, Box& box) {
  const VoxelGrid& g = b.g;
  if (g.count_nonempty(r) == 0) return false;
  if (depth == b.axes.size()) {
    const auto v = static_cast<std::uint32_t>(g.index(r.lo[0], r.lo[1], r.lo[2]));
    box = g.content[v];
    b.leaves.push_back(v);
    b.tree.push_back({.box = box, .slab = measured_slab(g, b.mesh, std::span(&v, 1), box, b.magnitude), .second = 0,
                      .voxel = v});
    return true;
  }
  const auto axis = static_cast<std::size_t>(b.axes[depth]);
  CellRange lo = r, hi = r;
  lo.hi[axis] = (r.lo[axis] + r.hi[axis]) / 2;
  hi.lo[axis] = lo.hi[axis] + 1;
  const bool lo_full = g.count_nonempty(lo) != 0, hi_full = g.count_nonempty(hi) != 0;
  if (!lo_full || !hi_full) return add_subtree(b, lo_full ? lo : hi, depth + 1, box);
  const std::size_t node = b.tree.size();
  const std::size_t first_leaf = b.leaves.size();
  b.tree.emplace_back();
  Box x, y;
  add_subtree(b, lo, depth + 1, x);
  const std::size_t second = b.tree.size();
  b.tree[node].second = static_cast<std::uint32_t>(second);
  add_subtree(b, hi, depth + 1, y);
  box = Box{x.lo.cwiseMin(y.lo), x.hi.cwiseMax(y.hi)};
  b.tree[node].box = box;
  const std::span<const std::uint32_t> voxels = std::span(b.leaves).subspan(first_leaf);
  std::uint32_t listings = 0;
  for (const std::uint32_t v : voxels) listings += g.offsets[v + 1] - g.offsets[v];
  b.tree[node].slab = listings <= kSlabExactListings ? measured_slab(g, b.mesh, voxels, box, b.magnitude)
                                                     : composed_slab(b.tree[node + 1], b.tree[second], box, b.magnitude);
  return true;
}

// The next float below / above a float (libm's nextafterf is a call per coordinate; a grid of
// a million faces rounds some ten million of them).
float float_down(float x) {
  if (x == 0) return -std::numeric_limits<float>::denorm_min();
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(x) + (x > 0 ? 0xffffffffu : 1u));
}
float float_up(float x) {
  if (x == 0) return std::numeric_limits<float>::denorm_min();
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(x) + (x > 0 ? 1u : 0xffffffffu));
}

// Whether the slab is worth testing (kThinSlab).
bool thin_slab(const Slab& s, const Box& box) {
  const auto [blo, bhi] = box_along(s.n, box);
  return s.hi - s.lo <= kThinSlab * (bhi - blo);
}

// A slab's interval [lo, hi] as a float middle and radius that hold it.
void float_interval(double lo, double hi, float& mid, float& radius) {
  float l = opaque_float(lo), h = opaque_float(hi);
  if (static_cast<double>(l) > lo) l = float_down(l);
  if (static_cast<double>(h) < hi) h = float_up(h);
  mid = 0.5f * (l + h);
  radius = float_up(std::max(mid - l, h - mid));  // covers their rounding
}

// A box (the double box lo, hi) as float centre and half sides that hold it.
void float_box(const Vec3& lo, const Vec3& hi, float* centre, float* half) {
  for (int k = 0; k < 3; ++k) {
    float l = static_cast<float>(lo[k]), h = static_cast<float>(hi[k]);
    if (static_cast<double>(l) > lo[k]) l = float_down(l);
    if (static_cast<double>(h) < hi[k]) h = float_up(h);
    centre[k] = 0.5f * (l + h);
    half[k] = float_up(std::max(centre[k] - l, h - centre[k]));  // covers their rounding
  }
}

std::uint32_t leaf_ref(const BinaryNode& n) { return TreeNode::kLeaf | n.voxel; }

// Node of the 4-ary tree for binary inner node i: its children, or for an inner child its two
// children, as lanes. Returns the node's index.
std::uint32_t add_node(VoxelGrid& g, const std::vector<BinaryNode>& bin, std::uint32_t i) {
  const auto index = static_cast<std::uint32_t>(g.tree.size());
  g.tree.emplace_back();
  g.slabs.emplace_back();
  std::array<std::uint32_t, 4> lanes{};
  int n = 0;
  for (const std::uint32_t c : {i + 1, bin[i].second}) {
    if (bin[c].leaf()) {
      lanes[static_cast<std::size_t>(n++)] = c;
    } else {
      lanes[static_cast<std::size_t>(n++)] = c + 1;
      lanes[static_cast<std::size_t>(n++)] = bin[c].second;
    }
  }
  for (int s = 0; s < 4; ++s) {
    const auto u = static_cast<std::size_t>(s);
    float centre[3] = {0, 0, 0}, half[3] = {-1e30f, -1e30f, -1e30f};  // unused: ref kNone, masked
    float normal[3] = {1, 0, 0}, mid = 0, radius = 0;
    std::uint32_t ref = TreeNode::kNone;
    if (s < n) {
      const BinaryNode& b = bin[lanes[u]];
      float_box(b.box.lo, b.box.hi, centre, half);
      for (int k = 0; k < 3; ++k) normal[k] = static_cast<float>(b.slab.n[k]);  // exact: n is float-valued
      float_interval(b.slab.lo, b.slab.hi, mid, radius);
      if (thin_slab(b.slab, b.box)) g.tree[index].thin |= 1u << s;
      ref = b.leaf() ? leaf_ref(b) : add_node(g, bin, lanes[u]);
    }
    TreeNode& t = g.tree[index];  // add_node may have moved the vectors
    t.cx[u] = centre[0], t.cy[u] = centre[1], t.cz[u] = centre[2];
    t.hx[u] = half[0], t.hy[u] = half[1], t.hz[u] = half[2];
    t.child[u] = ref;
    TreeSlabs& l = g.slabs[index];
    l.nx[u] = normal[0], l.ny[u] = normal[1], l.nz[u] = normal[2];
    l.sm[u] = mid, l.sr[u] = radius;
  }
  return index;
}

void build_tree(VoxelGrid& g, const Polyhedron& mesh, const std::vector<int>& axes) {
  g.tree.clear();
  g.slabs.clear();
  g.root = VoxelGrid::kNoRoot;
  CellRange all;
  for (std::size_t k = 0; k < 3; ++k) all.hi[k] = g.cells[k] - 1;
  TreeBuild b{g, mesh, axes, g.container.scale + g.container.size.maxCoeff(), {}, {}};
  Box box;
  if (!add_subtree(b, all, 0, box)) return;
  const std::vector<BinaryNode>& bin = b.tree;
  float_box(bin[0].box.lo, bin[0].box.hi, g.root_centre.data(), g.root_half.data());
  for (std::size_t k = 0; k < 3; ++k) g.root_normal[k] = static_cast<float>(bin[0].slab.n[static_cast<Eigen::Index>(k)]);
  float_interval(bin[0].slab.lo, bin[0].slab.hi, g.root_sm, g.root_sr);
  g.root_thin = thin_slab(bin[0].slab, bin[0].box);
  g.root = bin[0].leaf() ? leaf_ref(bin[0]) : add_node(g, bin, 0);
}

}  // namespace

void VoxelGrid::build_face_voxels() const {
  // From the voxel lists in voxel order, so each face's voxels come out increasing.
  face_offsets.assign(face_count + 1, 0);
  for (const std::uint32_t f : faces) ++face_offsets[f + 1];
  for (std::size_t f = 0; f < face_count; ++f) face_offsets[f + 1] += face_offsets[f];
  face_voxels.resize(faces.size());
  std::vector<std::uint32_t> fill(face_offsets.begin(), face_offsets.end() - 1);
  for (std::size_t v = 0; v + 1 < offsets.size(); ++v)
    for (std::uint32_t n = offsets[v]; n < offsets[v + 1]; ++n) face_voxels[fill[faces[n]]++] = static_cast<std::uint32_t>(v);
}

FloatBox outward(const Box& b) {
  FloatBox f;
  for (int k = 0; k < 3; ++k) {
    f.lo[k] = static_cast<float>(b.lo[k]);
    f.hi[k] = static_cast<float>(b.hi[k]);
    if (static_cast<double>(f.lo[k]) > b.lo[k]) f.lo[k] = float_down(f.lo[k]);
    if (static_cast<double>(f.hi[k]) < b.hi[k]) f.hi[k] = float_up(f.hi[k]);
  }
  return f;
}

Box VoxelGrid::voxel_box(int i, int j, int k) const {
  const Vec3 lo = container.origin + Vec3(i * cell.x(), j * cell.y(), k * cell.z());
  return {lo, lo + cell};
}

int auto_halvings(const Polyhedron& mesh) {
  const std::size_t f = mesh.triangles.size();
  if (f < 2) return 3;
  int m = static_cast<int>(std::lround(std::log2(static_cast<double>(f))));
  // Size: cells no smaller than the mean face size sqrt(2 area) (volume / size^3 cells at
  // most). Not the longest edge: a cylinder's long slivers still part well across.
  double edge = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    edge += std::sqrt((b - a).cross(c - a).norm());
  }
  edge /= static_cast<double>(f);
  const Container c = make_container(mesh.vertices);
  if (edge > 0) {
    const double cells = c.size.prod() / (edge * edge * edge);
    if (cells >= 1) m = std::min(m, static_cast<int>(std::floor(std::log2(cells))) + 1);
  }
  return std::clamp(m, 3, 18);
}

std::uint32_t VoxelGrid::count_nonempty(const CellRange& r) const {
  if (r.empty()) return 0;
  const std::size_t sx = static_cast<std::size_t>(cells[0]) + 1, sy = static_cast<std::size_t>(cells[1]) + 1;
  auto at = [&](int i, int j, int k) {
    return occupied[static_cast<std::size_t>(i) + sx * (static_cast<std::size_t>(j) + sy * static_cast<std::size_t>(k))];
  };
  const int i0 = r.lo[0], j0 = r.lo[1], k0 = r.lo[2], i1 = r.hi[0] + 1, j1 = r.hi[1] + 1, k1 = r.hi[2] + 1;
  // Inclusion-exclusion in unsigned arithmetic: wraps cancel, the result is exact.
  return at(i1, j1, k1) - at(i0, j1, k1) - at(i1, j0, k1) - at(i1, j1, k0) + at(i0, j0, k1) + at(i0, j1, k0) +
         at(i1, j0, k0) - at(i0, j0, k0);
}

std::array<int, 3> halve_cells(const Vec3& size, int halvings) {
  std::array<int, 3> n{1, 1, 1};
  for (const int axis : halving_axes(size, halvings)) n[static_cast<std::size_t>(axis)] *= 2;
  return n;
}

VoxelGrid build_voxel_grid(const Polyhedron& mesh, int halvings) { return build_voxel_grid(mesh, halvings, is_closed(mesh)); }

VoxelGrid build_voxel_grid(const Polyhedron& mesh, int halvings, bool closed) {
  VoxelGrid g;
  g.container = make_container(mesh.vertices);
  g.cells = halve_cells(g.container.size, std::clamp(halvings, 0, kMaxHalvings));
  g.cell = g.container.size.cwiseQuotient(Vec3(g.cells[0], g.cells[1], g.cells[2]));
  g.inv_cell = g.cell.cwiseInverse();
  // Covers the rounding of voxel corners and of the separating-axis arithmetic.
  g.margin = 64 * DBL_EPSILON * (g.container.scale + g.container.size.maxCoeff());
  g.face_count = mesh.triangles.size();

  // (voxel, face) incidences in face order, then a counting sort into CSR. Reserved for every
  // voxel of every face's range (an upper bound: the test only removes): the pages past the
  // incidences found are never touched, so cost no memory, and the list never doubles (a
  // doubling held three times the list while copying).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hits;
  auto face_range = [&](std::uint32_t f) {
    const Triangle& tri = mesh.triangles[f];
    const Vec3 &p = mesh.vertices[tri[0]], &q = mesh.vertices[tri[1]], &r = mesh.vertices[tri[2]];
    return range_of(g, grown(Box{p.cwiseMin(q).cwiseMin(r), p.cwiseMax(q).cwiseMax(r)}, 2 * g.margin));
  };
  {
    std::size_t bound = 0;
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
      const CellRange r = face_range(f);
      if (!r.empty())
        bound += static_cast<std::size_t>(r.hi[0] - r.lo[0] + 1) * static_cast<std::size_t>(r.hi[1] - r.lo[1] + 1) *
                 static_cast<std::size_t>(r.hi[2] - r.lo[2] + 1);
    }
    hits.reserve(std::min(bound, 16 * mesh.triangles.size() + 1024));  // past that it may double
  }
  const Vec3 half = 0.5 * g.cell + Vec3::Constant(g.margin);
  const double magnitude = g.container.scale + g.container.size.maxCoeff();
  for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
    const Triangle& tri = mesh.triangles[f];
    const TriangleVerts t{mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]};
    const CellRange r = face_range(f);
    if (r.empty()) continue;
    // One voxel: the test would only repeat what cell_range found (the face's grown box meets it).
    const bool single = r.lo == r.hi;
    const TriangleBoxTest test(t, half, magnitude);
    for (int k = r.lo[2]; k <= r.hi[2]; ++k)
      for (int j = r.lo[1]; j <= r.hi[1]; ++j)
        for (int i = r.lo[0]; i <= r.hi[0]; ++i) {
          const Box vb = g.voxel_box(i, j, k);
          if (single || test.overlaps(0.5 * (vb.lo + vb.hi)))
            hits.emplace_back(static_cast<std::uint32_t>(g.index(i, j, k)), f);
        }
  }
  const std::size_t n = static_cast<std::size_t>(g.cells[0]) * g.cells[1] * g.cells[2];
  g.offsets.assign(n + 1, 0);
  for (const auto& h : hits) ++g.offsets[h.first + 1];
  for (std::size_t v = 0; v < n; ++v) g.offsets[v + 1] += g.offsets[v];
  g.faces.resize(hits.size());
  std::vector<std::uint32_t> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (const auto& h : hits) g.faces[fill[h.first]++] = h.second;
  std::vector<std::pair<std::uint32_t, std::uint32_t>>().swap(hits);  // freed before the parts are made

  // Content boxes: voxel (grown) cut to the union of its faces' boxes (grown).
  g.content.assign(n, Box{});
  g.face_parts.resize(g.faces.size());
  for (int k = 0; k < g.cells[2]; ++k)
    for (int j = 0; j < g.cells[1]; ++j)
      for (int i = 0; i < g.cells[0]; ++i) {
        const std::size_t v = g.index(i, j, k);
        if (g.voxel_empty(v)) continue;
        const Box vb = grown(g.voxel_box(i, j, k), g.margin);
        Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
        for (std::uint32_t n = g.offsets[v]; n < g.offsets[v + 1]; ++n) {
          const Triangle& tri = mesh.triangles[g.faces[n]];
          const Vec3 &p = mesh.vertices[tri[0]], &q = mesh.vertices[tri[1]], &r = mesh.vertices[tri[2]];
          const Box fb = grown(Box{p.cwiseMin(q).cwiseMin(r), p.cwiseMax(q).cwiseMax(r)}, g.margin);
          const Box part{vb.lo.cwiseMax(fb.lo), vb.hi.cwiseMin(fb.hi)};
          g.face_parts[n] = outward(part);
          lo = lo.cwiseMin(part.lo);
          hi = hi.cwiseMax(part.hi);
        }
        g.content[v] = Box{lo, hi};
      }
  // Summed-volume table of non-empty voxels.
  const std::size_t sx = static_cast<std::size_t>(g.cells[0]) + 1, sy = static_cast<std::size_t>(g.cells[1]) + 1;
  g.occupied.assign(sx * sy * (static_cast<std::size_t>(g.cells[2]) + 1), 0);
  auto at = [&](int i, int j, int k) -> std::uint32_t& {
    return g.occupied[static_cast<std::size_t>(i) + sx * (static_cast<std::size_t>(j) + sy * static_cast<std::size_t>(k))];
  };
  for (int k = 1; k <= g.cells[2]; ++k)
    for (int j = 1; j <= g.cells[1]; ++j)
      for (int i = 1; i <= g.cells[0]; ++i)
        at(i, j, k) = (g.voxel_empty(g.index(i - 1, j - 1, k - 1)) ? 0u : 1u) + at(i - 1, j, k) + at(i, j - 1, k) +
                      at(i, j, k - 1) - at(i - 1, j - 1, k) - at(i - 1, j, k - 1) - at(i, j - 1, k - 1) +
                      at(i - 1, j - 1, k - 1);

  build_tree(g, mesh, halving_axes(g.container.size, std::clamp(halvings, 0, kMaxHalvings)));
  if (closed) classify_voxels(g, mesh);
  return g;
}

CellRange cell_range(const VoxelGrid& g, const Box& b) { return range_of(g, b); }

CellRange intersect(const CellRange& a, const CellRange& b) {
  CellRange r;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = std::max(a.lo[k], b.lo[k]);
    r.hi[k] = std::min(a.hi[k], b.hi[k]);
  }
  return r;
}

TriangleBoxTest::TriangleBoxTest(const TriangleVerts& t, const Vec3& half, double magnitude)
    : lo_(t[0].cwiseMin(t[1]).cwiseMin(t[2])), hi_(t[0].cwiseMax(t[1]).cwiseMax(t[2])), half_(half) {
  const Vec3 e[3] = {t[1] - t[0], t[2] - t[1], t[0] - t[2]};
  axis_[0] = e[0].cross(e[1]);
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) axis_[1 + 3 * j + k] = Vec3::Unit(k).cross(e[j]);
  for (std::size_t i = 0; i < kAxes; ++i) {
    const Vec3& a = axis_[i];
    const double p0 = a.dot(t[0]), p1 = a.dot(t[1]), p2 = a.dot(t[2]);
    min_[i] = std::min({p0, p1, p2});
    max_[i] = std::max({p0, p1, p2});
    // Projections of points up to `magnitude` carry a few ulps of |a|_1 * magnitude (and the
    // axes' own rounding as much again): widened by that, with room.
    const double a1 = std::fabs(a.x()) + std::fabs(a.y()) + std::fabs(a.z());
    rad_[i] = half.x() * std::fabs(a.x()) + half.y() * std::fabs(a.y()) + half.z() * std::fabs(a.z()) +
              32 * DBL_EPSILON * a1 * (magnitude + half.maxCoeff());
  }
}

bool triangle_box_overlap(const Vec3& centre, const Vec3& half, const TriangleVerts& t) {
  const Vec3 v0 = t[0] - centre, v1 = t[1] - centre, v2 = t[2] - centre;
  auto separates = [&](const Vec3& a) {
    const double p0 = a.dot(v0), p1 = a.dot(v1), p2 = a.dot(v2);
    const double r = half.x() * std::fabs(a.x()) + half.y() * std::fabs(a.y()) + half.z() * std::fabs(a.z());
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  // The box's face normals (the triangle's bounding box against the box).
  for (int k = 0; k < 3; ++k)
    if (std::min({v0[k], v1[k], v2[k]}) > half[k] || std::max({v0[k], v1[k], v2[k]}) < -half[k]) return false;
  const Vec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
  if (separates(e[0].cross(e[1]))) return false;  // the triangle's plane
  for (const Vec3& edge : e)
    for (int k = 0; k < 3; ++k)
      if (separates(Vec3::Unit(k).cross(edge))) return false;
  return true;
}

}  // namespace asimov::collision
