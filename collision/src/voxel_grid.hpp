// Step 3 preprocessing: a body's container cut into 2^M voxels by M halvings of the longest
// cell side, each voxel listing (CSR) every face that touches it.
#pragma once
#include "face_test.hpp"
#include "minimax.hpp"
#include "asimov/collision/polyhedron.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace asimov::collision {

// Inclusive voxel index ranges per axis; empty when any lo > hi.
struct CellRange {
  std::array<int, 3> lo{0, 0, 0}, hi{-1, -1, -1};
  bool empty() const { return lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]; }
};

// A node of the halvings tree [ours], as step 3 reads it: two levels of halvings at once, so up
// to four children, their boxes side by side in float lanes (one SIMD test for all four). A
// child box is the union of its voxels' content boxes (local frame), rounded outward to float.
//
// [ours] Each child also has a slab (TreeSlabs, the same index as its node, kept apart so that
// the nodes near the root, whose slabs are not worth testing, stay two cache lines each).
struct alignas(64) TreeNode {
  static constexpr std::uint32_t kLeaf = 0x80000000u;  // child ref: kLeaf | voxel index, else a node index
  static constexpr std::uint32_t kNone = 0xffffffffu;  // an unused lane
  std::array<float, 4> cx{}, cy{}, cz{};  // children's centres
  std::array<float, 4> hx{}, hy{}, hz{};  // children's half sides
  std::array<std::uint32_t, 4> child{};
  std::uint32_t thin = 0;  // bit s: child s's slab is thin enough to be worth testing (kThinSlab)
};
// The children's slabs of a TreeNode: a unit normal n (the area-weighted mean normal of the
// faces in the child's voxels) and the interval sm +- sr of n . x over those faces' vertices,
// within the projection of its box. A patch of surface is thin along its own normal, so where two
// surfaces come near without crossing, their slabs part them long after their boxes (local
// axis-aligned, fat for a tilted patch) still meet (tree_descent.hpp).
struct TreeSlabs {
  std::array<float, 4> nx{}, ny{}, nz{};  // normals (unit, as stored)
  std::array<float, 4> sm{}, sr{};        // n . x within sm +- sr (rounded outward)
};
// A slab is tested only when its radius is at most this fraction of its box's along n (near the
// root the normals spread and the slab is the box again: the test would only cost).
constexpr double kThinSlab = 0.5;

// A box in float, rounded outward from the double box it stands for (half the bytes of a Box:
// the per-face parts are the largest part of a big mesh's grid, 1.5 per face at 1M faces).
struct FloatBox {
  float lo[3], hi[3];
};
FloatBox outward(const Box& b);

// Containment class of a voxel (docs/collision-method.md §6.1).
enum class VoxelClass : std::uint8_t { surface, outside, inside };

struct VoxelGrid {
  Container container;
  std::array<int, 3> cells{1, 1, 1};  // voxels per axis, product 2^M
  Vec3 cell = Vec3::Ones();           // voxel side lengths [mm]
  Vec3 inv_cell = Vec3::Ones();       // 1 / cell (cell_range multiplies: a division cost 5 % of a query)
  double margin = 0;                  // growth of each voxel in the triangle-box test [mm]
  std::vector<std::uint32_t> offsets; // CSR: faces of voxel v are faces[offsets[v] .. offsets[v+1])
  std::vector<std::uint32_t> faces;   // triangle indices
  std::vector<FloatBox> face_parts;   // parallel to faces: the voxel (grown) cut to the face's box
                                      //   (grown), holding every point of the face in the voxel
  // Inverse CSR, built on first voxels_of() (only the reference FacePairs asks; 10 bytes per face
  // at 1M faces): voxels of face f are face_voxels[face_offsets[f] .. face_offsets[f+1]).
  mutable std::vector<std::uint32_t> face_offsets;
  mutable std::vector<std::uint32_t> face_voxels;
  std::vector<VoxelClass> classes;    // per voxel; empty when the mesh is not closed
  std::vector<Box> content;           // per non-empty voxel: the voxel (grown by margin) cut to the
                                      //   union of its faces' boxes (grown): holds every face point
                                      //   inside the voxel, often much smaller than the voxel
  // The halvings tree [ours]: node = a cell of some halving level holding a non-empty voxel,
  // children = its two halves (a half with no non-empty voxel is dropped, a node with one child
  // is replaced by it), leaves = non-empty voxels; stored two levels per TreeNode. Step 3
  // descends both bodies' trees together, so only subtrees whose boxes meet are visited.
  std::vector<TreeNode> tree;           // nodes; the root's box and ref below
  std::vector<TreeSlabs> slabs;         // per node, its children's slabs
  std::array<float, 3> root_centre{}, root_half{};
  std::array<float, 3> root_normal{1, 0, 0};  // the root's slab (TreeNode)
  float root_sm = 0, root_sr = 0;
  bool root_thin = false;
  std::uint32_t root = kNoRoot;         // kNoRoot when the mesh has no face
  static constexpr std::uint32_t kNoRoot = 0xffffffffu;
  std::vector<std::uint32_t> occupied;  // summed-volume table of non-empty voxels,
                                        //   (nx+1)(ny+1)(nz+1): count with indices < (i, j, k)
  std::size_t face_count = 0;         // triangles of the mesh

  std::size_t voxel_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(cells[0]) * (j + static_cast<std::size_t>(cells[1]) * k);
  }
  bool voxel_empty(std::size_t v) const { return offsets[v] == offsets[v + 1]; }
  std::span<const std::uint32_t> faces_in(std::size_t v) const {
    return {faces.data() + offsets[v], faces.data() + offsets[v + 1]};
  }
  std::span<const FloatBox> face_parts_in(std::size_t v) const {
    return {face_parts.data() + offsets[v], face_parts.data() + offsets[v + 1]};
  }
  std::span<const std::uint32_t> voxels_of(std::uint32_t f) const {
    if (face_offsets.empty()) build_face_voxels();
    return {face_voxels.data() + face_offsets[f], face_voxels.data() + face_offsets[f + 1]};
  }
  void build_face_voxels() const;
  Box voxel_box(int i, int j, int k) const;  // local, not grown
  // Non-empty voxels in a range (0 for an empty range), in O(1).
  std::uint32_t count_nonempty(const CellRange& r) const;
};

constexpr int kMaxHalvings = 24;

// M for a body from a cost model of its face count and size (bench/bench_m_sweep.cpp,
// docs/collision.md §7): about one face per voxel, M = round(log2 F) (the fastest mean measured
// is within about 2 of log2 F from 400 to 50,000 faces, for the flat scan and for the halvings
// tree), but no voxel much smaller than the mean face size sqrt(2 area); within [3, 18].
int auto_halvings(const Polyhedron& mesh);

// Cells per axis after M halvings, each doubling the axis whose cells are longest (ties x, y, z).
std::array<int, 3> halve_cells(const Vec3& size, int halvings);

VoxelGrid build_voxel_grid(const Polyhedron& mesh, int halvings);
// The same when the caller knows whether the mesh is closed (is_closed: voxel classes only then).
VoxelGrid build_voxel_grid(const Polyhedron& mesh, int halvings, bool closed);

// Voxels of `grid` that a local box overlaps (clamped to the grid; empty if outside).
CellRange cell_range(const VoxelGrid& grid, const Box& local_box);
CellRange intersect(const CellRange& a, const CellRange& b);

// Akenine-Moller (2001) separating-axis test of a closed triangle against an axis-aligned box.
// Conservative: it can only err toward "overlap" (callers grow the box for rounding).
bool triangle_box_overlap(const Vec3& centre, const Vec3& half, const TriangleVerts& t);

// The same test for one triangle against many boxes of one half size (a grid's voxels): the
// thirteen axes, the triangle's extent along each and the boxes' radius are computed once, so a
// box costs one projection of its centre per axis (the voxelisation's inner loop). Rounding:
// every radius is widened by a few ulps of `magnitude` (the largest coordinate of triangle and
// centres), so it errs only toward "overlap", at least as far as triangle_box_overlap does.
class TriangleBoxTest {
 public:
  TriangleBoxTest(const TriangleVerts& t, const Vec3& half, double magnitude);
  bool overlaps(const Vec3& centre) const {
    for (int k = 0; k < 3; ++k)
      if (lo_[k] - centre[k] > half_[k] || hi_[k] - centre[k] < -half_[k]) return false;
    for (std::size_t i = 0; i < kAxes; ++i) {
      const double p = axis_[i].dot(centre);
      if (min_[i] - p > rad_[i] || max_[i] - p < -rad_[i]) return false;
    }
    return true;
  }

 private:
  static constexpr std::size_t kAxes = 10;  // the triangle's normal, then edge x box axis
  Vec3 lo_, hi_, half_;
  std::array<Vec3, kAxes> axis_;
  std::array<double, kAxes> min_, max_, rad_;
};

}  // namespace asimov::collision
