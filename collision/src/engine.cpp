// The four steps wired together. Per body: preprocessing (container, voxel grid, shells)
// done lazily for bodies in an enabled pair; per pose: sphere centre, world box and world
// vertices cached by pose version, so a static body computes them once. Buffers are members
// and reused, so after the first checks no query allocates.
#include "asimov/collision/engine.hpp"

#include "container_gap.hpp"
#include "containment.hpp"
#include "distance_descent.hpp"
#include "distance_tree.hpp"
#include "face_distance.hpp"
#include "face_plane.hpp"
#include "face_test.hpp"
#include "minimax.hpp"
#include "asimov/collision/participation.hpp"
#include "tree_descent.hpp"
#include "voxel_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>

namespace asimov::collision {
namespace {

// One face in world coordinates, valid when version == its body's version (step 4 cache).
// Two cache lines with its version: at 50,000 faces the cache is far larger than L2, and a
// separate version array cost a third miss per face.
struct alignas(64) WorldFace {
  TriangleVerts t;  // world vertices (transform_vertex of the local ones)
  Vec3 lo, hi;      // their bounding box
  std::uint64_t version = 0;
};

// Face pairs already tested in the current body pair [ours]: a face spans many voxels, so one
// pair meets in several voxel pairs; a repeat would get the same answer (no contact, or the
// query would have ended). Open addressing over a fixed table, cleared by a stamp per body
// pair; a pair that finds no free slot within a few probes is simply not remembered (tested
// again), so the table never grows and never allocates after construction.
template <int kBits = 12>
class TestedPairs {
 public:
  void next_body_pair() {
    if (++now_ == 0) {  // wrapped: forget every old stamp
      std::fill(stamp_.begin(), stamp_.end(), 0);
      now_ = 1;
    }
  }
  // True when (fa, fb) was recorded since next_body_pair(); records it otherwise.
  bool seen_or_insert(std::uint32_t fa, std::uint32_t fb) {
    const std::uint64_t key = (std::uint64_t{fa} << 32) | fb;
    std::size_t i = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - kBits));
    for (int probe = 0; probe < kProbes; ++probe, i = (i + 1) & (kSlots - 1)) {
      if (stamp_[i] != now_) {
        stamp_[i] = now_;
        key_[i] = key;
        return false;
      }
      if (key_[i] == key) return true;
    }
    return false;
  }

 private:
  static constexpr int kProbes = 8;
  static constexpr std::size_t kSlots = std::size_t{1} << kBits;
  std::vector<std::uint64_t> key_ = std::vector<std::uint64_t>(kSlots);
  std::vector<std::uint32_t> stamp_ = std::vector<std::uint32_t>(kSlots);
  std::uint32_t now_ = 0;
};

// World vertex cache page (Body::vertex_pages).
constexpr std::uint32_t kVertexPage = 64;
struct VertexPage {
  std::array<Vec3, kVertexPage> v;
  std::array<std::uint64_t, kVertexPage> version{};  // 0: never mapped (versions start at 1)
};

// A body's shells for the distance query's hull bound: each shell's vertices, contiguous, and
// a sphere holding them (body frame). A body made of separate convex pieces (the built-in
// links: boxes and cylinders side by side) is far better bounded piece by piece than by the
// hull of the whole, which may hold the other body.
struct HullParts {
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> begin{0};  // shell k: vertices[begin[k], begin[k + 1])
  std::vector<Vec3> centre;
  std::vector<double> radius;
  std::size_t count() const { return centre.size(); }
  std::span<const Vec3> shell(std::size_t k) const {
    return std::span<const Vec3>(vertices).subspan(begin[k], begin[k + 1] - begin[k]);
  }
};

struct Body {
  BodyDef def;
  // The body's mesh: the caller's when BodyDef::mesh_ref is set (not copied), else def.mesh.
  const Polyhedron& mesh() const { return def.mesh_ref ? *def.mesh_ref : def.mesh; }
  Pose pose = Pose::Identity();
  std::uint64_t version = 1;        // bumped by every set_pose
  Container container;              // step 2 basic axes, local
  bool closed = false;              // containment applies (§6.1)
  std::vector<std::vector<std::uint32_t>> shells;  // per shell, a few of its vertices (shell_samples)
  std::optional<VoxelGrid> grid;    // step 3, built on first use
  std::unique_ptr<DistanceTree> distance_tree;  // the distance query's face tree, built on first use
  std::unique_ptr<HullParts> hull_parts;         // the distance query's per-shell hulls, built on first use
  std::vector<Vec3> world;          // world vertices, all valid when world_version == version
  std::uint64_t world_version = 0;  //   (allocated on the first full mapping: the exact containment test)
  // Else vertex i mapped alone (step 4), valid when its page's version[i % kVertexPage] ==
  // version: pages allocated at add_body for bodies of at most kEagerFaces faces, on first use
  // above (a dense cache was 32 bytes per vertex, 16 per face, for every body at load).
  std::vector<std::unique_ptr<VertexPage>> vertex_pages;
  // World triangle + box of face f (step 4 cache), in pages of kFacePage faces: a body of more
  // than kEagerFaces faces gets a page on first use (a 1M-face object far from the arm touches
  // few; a dense cache was 128 bytes per face), smaller ones all pages at preprocessing.
  std::vector<std::unique_ptr<WorldFace[]>> face_pages;
  int halvings = 9;                 // M in use (resolved from def.halvings, kAutoHalvings = cost model)
  Box box;                          // world minimax box, valid when box_version == version
  std::uint64_t box_version = 0;
  Vec3 sphere_centre = Vec3::Zero();// world centre of the vertex sphere, valid when
  std::uint64_t sphere_version = 0; //   sphere_version == version
};

TriangleVerts triangle_at(const std::vector<Vec3>& v, const Triangle& t) { return {v[t[0]], v[t[1]], v[t[2]]}; }

// Exact point-in-solid in world coordinates (the reference answer shared with brute force).
bool world_point_inside(const Vec3& w, const std::vector<Vec3>& world, const Polyhedron& mesh) {
  return point_in_solid(w, world, mesh.triangles) != PointClass::outside;
}

  // Squared distance of two axis-aligned boxes (0 when they overlap): a lower bound on the
// squared distance of anything inside them.
double box_distance2(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max(alo[k] - bhi[k], blo[k] - ahi[k]);
    s += g > 0 ? g * g : 0.0;
  }
  return s;
}

// World-face cache pages (Body::face_pages): faces per page, and the size up to which every
// page is allocated at preprocessing (no allocation in queries; larger bodies page on demand).
constexpr std::uint32_t kFacePage = 64;
constexpr std::size_t kEagerFaces = 65536;

// Vertices per shell tried by voxel class before the exact point-in-solid test (contained).
constexpr std::size_t kShellSamples = 16;
// Distance: bodies with at most this many vertices get the hull bound (hull_gap) before the
// voxel descent, with at most this many directions.
constexpr std::size_t kHullGapVertices = 2048;
constexpr int kHullGapIterations = 24;
// ... and it goes on up to this multiple of the cut-off: a caller keeping the answer "beyond" as
// a lower bound for later poses (continuous checking's anchors) gets a better one for little.
constexpr double kHullGapEnough = 2;
// The hull bound goes shell by shell when the two bodies have at most this many shell pairs.
constexpr std::size_t kHullPartPairs = 16;

HullParts hull_parts_of(const Polyhedron& mesh) {
  HullParts p;
  for (const std::vector<std::uint32_t>& shell : shell_members(mesh)) {
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (const std::uint32_t v : shell) {
      p.vertices.push_back(mesh.vertices[v]);
      lo = lo.cwiseMin(mesh.vertices[v]);
      hi = hi.cwiseMax(mesh.vertices[v]);
    }
    const Vec3 c = 0.5 * (lo + hi);
    double r = 0;
    for (std::uint32_t i = p.begin.back(); i < p.vertices.size(); ++i) r = std::max(r, (p.vertices[i] - c).norm());
    p.centre.push_back(c);
    p.radius.push_back(r + 1e-12 * (r + c.norm()));  // the norms' rounding, outward
    p.begin.push_back(static_cast<std::uint32_t>(p.vertices.size()));
  }
  return p;
}

// [ours] Lower bound on the distance of two bodies from their shells (HullParts): the least over
// shell pairs of the better of the two spheres' bound and the hulls' (hull_gap). Every face lies
// in its shell's hull, and a body inside the other lies inside one of its shells' hulls (a
// connected set crossing no face stays on one side of each shell), so the least is a bound on
// the surfaces' distance and a positive one rules out containment. Shell pairs go nearest
// spheres first; one that cannot reach `prove` (the bound the caller needs) ends the search with
// -infinity (the least of the pairs so far would not bound the others). `enough`: as
// hull_gap's, for every pair. Each pair starts cold (one warm direction for the whole body pair
// misleads the other pieces); on return `guess` holds the direction of the pair that is least.
double parts_gap(const HullParts& pa, const HullParts& pb, const Pose& a_from_b, double slack, double enough,
                 double prove, Vec3* guess) {
  struct Candidate {
    double sphere;
    std::uint32_t i, j;
  };
  std::array<Candidate, kHullPartPairs> order;
  std::size_t n = 0;
  for (std::uint32_t i = 0; i < pa.count(); ++i)
    for (std::uint32_t j = 0; j < pb.count(); ++j) {
      const Vec3 cb = a_from_b * pb.centre[j];
      const double d = (pa.centre[i] - cb).norm();
      order[n++] = {d - pa.radius[i] - pb.radius[j] - slack - 1e-12 * (d + pa.centre[i].norm() + cb.norm()), i, j};
    }
  std::sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n),
            [](const Candidate& x, const Candidate& y) { return x.sphere < y.sphere; });
  double least = INFINITY;
  Vec3 best_dir = *guess;
  for (std::size_t k = 0; k < n; ++k) {
    const Candidate& c = order[k];
    if (c.sphere >= least) break;  // this pair and the rest are no nearer than the least
    double bound = c.sphere;
    Vec3 dir = Vec3::Zero();
    if (bound < enough)
      bound = std::max(bound, hull_gap(pa.shell(c.i), pb.shell(c.j), a_from_b, slack, enough, kHullGapIterations, prove, &dir));
    if (bound < least) least = bound, best_dir = dir;
    if (least < prove) return -INFINITY;
  }
  *guess = best_dir;
  return least;
}

}  // namespace

struct Engine::Impl {
  std::vector<Body> bodies;
  Participation participation;
  std::vector<std::uint32_t> pair_count;  // enabled pairs per body (step 2 test order)
  std::vector<BodyId> not_static;         // the bodies that may move, in id order
  double default_clearance = 0;           // check() / check_pairs()
  double clearance = 0;                   // of the query running (QueryRequest::clearance_mm)
  // A faces of the current voxel pair (index, world face), reused (no allocation per pose).
  // Its plane (face_plane.hpp) is computed here on first use: most kept faces never reach the
  // prefilter, and a plane per cached face made the cache a third larger.
  struct Kept {
    std::uint32_t f;
    const WorldFace* w;
    bool has_plane;
    FacePlane plane;
  };
  std::vector<Kept> a_faces;
  TestedPairs<> tested;

  static bool never_tested(const Body& a, const Body& b) {
    return (a.def.group >= 0 && a.def.group == b.def.group) || (a.def.is_static && b.def.is_static);
  }

  const Box& world_box(Body& b) {
    if (b.box_version != b.version) {
      b.box = minimax_box(b.container, b.pose);
      b.box_version = b.version;
    }
    return b.box;
  }
  const Vec3& world_sphere_centre(Body& b) {
    if (b.sphere_version != b.version) {
      b.sphere_centre = b.pose * b.container.centre();
      b.sphere_version = b.version;
    }
    return b.sphere_centre;
  }
  const std::vector<Vec3>& world(Body& b) {
    if (b.world_version != b.version) {
      transform_vertices(b.mesh().vertices, b.pose, b.world);
      b.world_version = b.version;
    }
    return b.world;
  }
  // One world vertex, mapped on first use in this pose: step 4 touches few of a large mesh's
  // vertices, and mapping them all was 50 us per query at 50,000 faces.
  static const Vec3& world_vertex(Body& b, std::uint32_t i) {
    if (b.world_version == b.version) return b.world[i];
    std::unique_ptr<VertexPage>& page = b.vertex_pages[i / kVertexPage];
    if (!page) page = std::make_unique<VertexPage>();  // large bodies only (kEagerFaces)
    const std::uint32_t k = i % kVertexPage;
    if (page->version[k] != b.version) {
      page->v[k] = transform_vertex(b.pose, b.mesh().vertices[i]);
      page->version[k] = b.version;
    }
    return page->v[k];
  }
  static TriangleVerts world_triangle(Body& b, std::uint32_t f) {
    const Triangle& t = b.mesh().triangles[f];
    return {world_vertex(b, t[0]), world_vertex(b, t[1]), world_vertex(b, t[2])};
  }
  static void prefetch_face(const Body& b, std::uint32_t f) {
    const WorldFace* page = b.face_pages[f / kFacePage].get();
    if (!page) return;
    const char* w = reinterpret_cast<const char*>(page + f % kFacePage);
    __builtin_prefetch(w);
    __builtin_prefetch(w + 64);
  }
  static const WorldFace& world_face(Body& b, std::uint32_t f) {
    std::unique_ptr<WorldFace[]>& page = b.face_pages[f / kFacePage];
    if (!page) page = std::make_unique<WorldFace[]>(kFacePage);  // large bodies only (kEagerFaces)
    WorldFace& w = page[f % kFacePage];
    if (w.version != b.version) {
      w.t = world_triangle(b, f);
      w.lo = w.t[0].cwiseMin(w.t[1]).cwiseMin(w.t[2]);
      w.hi = w.t[0].cwiseMax(w.t[1]).cwiseMax(w.t[2]);
      w.version = b.version;
    }
    return w;
  }
  // Boxes farther apart than `pad` on some axis. With pad = 0 this is the exact bounding-box
  // rejection triangles_intersect starts with (min/max do not round); with a clearance c,
  // pad = 2c + margin, so no pair within c of each other is dropped.
  static bool boxes_disjoint(const Vec3& xlo, const Vec3& xhi, const Vec3& ylo, const Vec3& yhi, double pad) {
    // Branch-free on purpose: the compares are summed (not `||`), so all six run without jumps.
    return ((xlo.x() > yhi.x() + pad) + (ylo.x() > xhi.x() + pad) + (xlo.y() > yhi.y() + pad) +
            (ylo.y() > xhi.y() + pad) + (xlo.z() > yhi.z() + pad) + (ylo.z() > xhi.z() + pad)) != 0;
  }
  // The world-face cache (world_face), which step 4 and the distance query's leaves read.
  static void prepare_faces(Body& b) {
    const std::size_t faces = b.mesh().triangles.size();
    if (!b.face_pages.empty() || faces == 0) return;
    b.face_pages.resize((faces + kFacePage - 1) / kFacePage);
    if (faces <= kEagerFaces)
      for (auto& page : b.face_pages) page = std::make_unique<WorldFace[]>(kFacePage);
  }
  static void preprocess(Body& b) {
    if (b.grid) return;
    prepare_faces(b);
    b.grid = build_voxel_grid(b.mesh(), b.halvings, b.closed);
    b.shells = shell_samples(b.mesh(), kShellSamples);
  }

  // Where point p (in x's frame; mapped by the pair's relative pose, its rounding within ε_r)
  // is by x's voxel classes: 1 inside, 0 outside (every voxel within the margin agrees), -1
  // undecided (then only the exact test in world coordinates can tell).
  static int voxel_verdict(const Body& x, const Vec3& p, double margin) {
    const CellRange r = cell_range(*x.grid, Box{p.array() - margin, p.array() + margin});
    if (r.empty()) return 0;  // outside the container
    bool all_in = true, all_out = true;
    for (int k = r.lo[2]; k <= r.hi[2]; ++k)
      for (int j = r.lo[1]; j <= r.hi[1]; ++j)
        for (int i = r.lo[0]; i <= r.hi[0]; ++i) {
          const VoxelClass c = x.grid->classes[x.grid->index(i, j, k)];
          all_in = all_in && c == VoxelClass::inside;
          all_out = all_out && c == VoxelClass::outside;
        }
    return all_in ? 1 : all_out ? 0 : -1;
  }

  // §6.1, called once no faces meet: each shell of one body lies wholly inside or wholly
  // outside the other (it is connected and crosses no face), so any of its vertices decides
  // [ours]. The sampled vertices are tried by voxel class first; only when none is decided
  // there does the first one go to the exact point-in-solid test (O(faces), and it needs all
  // of the outer body's world vertices).
  bool contained(BodyId ia, BodyId ib, const Pose& a_from_b, double margin, Contact& c) {
    for (const bool a_outer : {true, false}) {
      Body& o = bodies[a_outer ? ia : ib];
      Body& in = bodies[a_outer ? ib : ia];
      if (!o.closed) continue;
      for (const std::vector<std::uint32_t>& shell : in.shells) {
        int verdict = -1;
        std::uint32_t v = shell.front();
        for (const std::uint32_t s : shell) {
          const Vec3& local = in.mesh().vertices[s];
          const Vec3 p = a_outer ? Vec3(a_from_b * local)
                                 : Vec3(a_from_b.linear().transpose() * (local - a_from_b.translation()));
          verdict = voxel_verdict(o, p, margin);
          if (verdict >= 0) {
            v = s;
            break;
          }
        }
        if (verdict < 0) verdict = world_point_inside(world_vertex(in, v), world(o), o.mesh()) ? 1 : 0;
        if (verdict == 1) {
          c = Contact{.kind = ContactKind::containment, .body_a = ia, .body_b = ib, .point = world_vertex(in, v)};
          return true;
        }
      }
    }
    return false;
  }

  // A voxel pair [ours]: a contact point of faces fa, fb lies in a voxel of A listing fa and
  // one of B listing fb, and that voxel pair is visited too; so here only the part of each face
  // inside its voxel matters. Faces whose part (local box) misses the other voxel's box mapped
  // into their frame are dropped before any world vertex is computed; B faces whose world box
  // misses the union of the kept A faces' boxes are dropped next. Then each kept B face against
  // each kept A face: exact bounding-box rejection, pairs already tested in this body pair
  // skipped, the plane prefilter (face_plane.hpp, sound), then the exact test. True at the
  // first contact (res filled).
  bool visit_voxel_pair(BodyId ia, BodyId ib, std::uint32_t va, std::uint32_t vb, const NodePair& p, double grow,
                        double pad, QueryResult& res) {
    Body& a = bodies[ia];
    Body& b = bodies[ib];
    const VoxelGrid& ga = *a.grid;
    const VoxelGrid& gb = *b.grid;
    if (res.counts.voxel_pairs++ == 0) ++res.counts.pairs_after_voxels;
    // The float centre, reach and grow of the descent: conservative (tree_descent.hpp). The
    // other voxel's interval per axis is computed once per voxel pair, and the six comparisons
    // per face are combined without branches (the outcome is data-dependent: a branch per
    // comparison mispredicted often).
    struct Window {
      double lo[3], hi[3];
    };
    auto window = [grow](const float* centre, const float* reach) {
      Window w;
      for (int k = 0; k < 3; ++k) {
        const double c = centre[k], r = static_cast<double>(reach[k]) + grow;
        w.lo[k] = c - r;
        w.hi[k] = c + r;
      }
      return w;
    };
    auto misses = [](const FloatBox& part, const Window& w) {  // float parts, rounded outward
      return ((part.lo[0] > w.hi[0]) + (part.hi[0] < w.lo[0]) + (part.lo[1] > w.hi[1]) +
              (part.hi[1] < w.lo[1]) + (part.lo[2] > w.hi[2]) + (part.hi[2] < w.lo[2])) != 0;
    };
    const Window in_a = window(p.y_centre_a, p.y_reach_a), in_b = window(p.x_centre_b, p.x_reach_b);
    a_faces.clear();
    Vec3 ulo = Vec3::Constant(INFINITY), uhi = Vec3::Constant(-INFINITY);  // union of kept A boxes
    const auto fas = ga.faces_in(va);
    const auto pas = ga.face_parts_in(va);
    // Two passes: the kept faces first, their cached world faces prefetched (at 50,000 faces
    // the cache is far larger than L2, and the misses now overlap), then the world faces.
    for (std::size_t n = 0; n < fas.size(); ++n)
      if (!misses(pas[n], in_a)) {
        Kept& k = a_faces.emplace_back();
        k.f = fas[n];
        k.has_plane = false;
        prefetch_face(a, k.f);
      }
    if (a_faces.empty()) return false;
    for (Kept& k : a_faces) {
      k.w = &world_face(a, k.f);
      ulo = ulo.cwiseMin(k.w->lo);
      uhi = uhi.cwiseMax(k.w->hi);
    }
    const auto fbs = gb.faces_in(vb);
    const auto pbs = gb.face_parts_in(vb);
    for (std::size_t n = 0; n < fbs.size(); ++n) {
      if (misses(pbs[n], in_b)) continue;
      const std::uint32_t fb = fbs[n];
      res.counts.face_pairs += a_faces.size();
      const WorldFace& wb = world_face(b, fb);
      // Missing the union box, it misses every kept A face's box (exact min/max): a bounding-
      // box rejection of all its pairs at once.
      if (boxes_disjoint(ulo, uhi, wb.lo, wb.hi, pad)) continue;
      bool b_has_plane = false;
      FacePlane b_plane{Vec3::Zero(), Vec3::Zero()};
      for (Kept& k : a_faces) {
        const WorldFace& wa = *k.w;
        // Disjoint bounding boxes: triangles_intersect would say no (min/max are exact).
        if (boxes_disjoint(wa.lo, wa.hi, wb.lo, wb.hi, pad)) continue;
        if (tested.seen_or_insert(k.f, fb)) continue;
        // Planes: strictly one side of the other's plane, exactly; triangles_intersect says no.
        if (!b_has_plane) {
          b_plane = face_plane(wb.t);
          b_has_plane = true;
        }
        bool apart = plane_separates(b_plane, wb.t, wa.t);
        if (!apart) {
          if (!k.has_plane) {
            k.plane = face_plane(wa.t);
            k.has_plane = true;
          }
          apart = plane_separates(k.plane, wa.t, wb.t);
        }
        if (!apart && triangles_intersect(wa.t, wb.t)) {
          res.collided = true;
          res.contact = Contact{.body_a = ia, .body_b = ib, .face_a = k.f, .face_b = fb,
                                .point = contact_point(wa.t, wb.t)};
          return true;
        }
        Vec3 pa, pb;
        if (double d = 0; clearance > 0 && triangles_within(wa.t, wb.t, clearance, d, pa, pb)) {
          res.collided = true;
          res.contact = Contact{.kind = ContactKind::clearance, .distance = d, .body_a = ia, .body_b = ib,
                                .face_a = k.f, .face_b = fb, .point = 0.5 * (pa + pb)};
          return true;
        }
      }
    }
    return false;
  }

  // Gap stepping's lower bound on the pair's distance (docs/collision-method.md §6.3), from the
  // world boxes and sphere centres step 2 caches per pose, so a body is placed once per pose.
  double pair_gap(BodyId ia, BodyId ib, double margin) {
    Body& a = bodies[ia];
    Body& b = bodies[ib];
    return container_gap(PlacedContainer{world_box(a), world_sphere_centre(a), a.container.radius},
                         PlacedContainer{world_box(b), world_sphere_centre(b), b.container.radius}, margin);
  }

  double margin_of(BodyId ia, BodyId ib) const {
    const Body& a = bodies[ia];
    const Body& b = bodies[ib];
    return relative_margin(a.container, a.pose, b.container, b.pose);
  }
  bool test_pair(BodyId ia, BodyId ib, QueryResult& res) { return test_pair(ia, ib, margin_of(ia, ib), res); }
  bool test_pair(BodyId ia, BodyId ib, double margin, QueryResult& res) {
    Body& a = bodies[ia];
    Body& b = bodies[ib];
    // Step 2: [ours] the vertex spheres first (the cheapest), the world minimax boxes (the
    // thesis), then [ours] the oriented containers.
    const double grow = clearance + margin;
    if (spheres_separated(world_sphere_centre(a), a.container.radius, world_sphere_centre(b), b.container.radius, grow))
      return false;
    // A body's world box is computed once per pose and shared by all its pairs (the thesis'
    // reason for it). When this pair would compute one for itself alone (a moving body in no
    // other enabled pair), the oriented boxes go first: they reject most of what the world
    // boxes would, and the world boxes still follow.
    const bool box_alone = (a.box_version != a.version && pair_count[ia] <= 1) ||
                           (b.box_version != b.version && pair_count[ib] <= 1);
    if (!box_alone && separated(world_box(a), world_box(b), grow)) return false;
    const Pose a_from_b = relative_pose(a.pose, b.pose);
    if (containers_separated(a.container, b.container, a_from_b, grow)) return false;
    if (box_alone && separated(world_box(a), world_box(b), grow)) return false;
    ++res.counts.pairs_after_minimax;
    return steps_3_4(ia, ib, a_from_b, margin, grow, res);
  }

  // Out of line: most pairs end in step 2, and with steps 3-4 inlined test_pair carried their
  // frame and saved registers on every call.
  [[gnu::noinline]] bool steps_3_4(BodyId ia, BodyId ib, const Pose& a_from_b, double margin, double grow,
                                   QueryResult& res) {
    Body& a = bodies[ia];
    Body& b = bodies[ib];
    preprocess(a);
    preprocess(b);
    const double pad = clearance > 0 ? 2 * clearance + margin : 0.0;
    // Steps 3 and 4, streamed: every voxel pair the descent finds goes to the face tests at
    // once; the first hit ends the query.
    const NodeTest nt(a_from_b, grow, a.container.scale, b.container.scale);
    tested.next_body_pair();
    if (descend(*a.grid, *b.grid, nt, [&](std::uint32_t va, std::uint32_t vb, const NodePair& p) {
          return visit_voxel_pair(ia, ib, va, vb, p, nt.grow, pad, res);
        }))
      return true;
    // §6.1: no faces meet, but one body may lie inside the other.
    if (contained(ia, ib, a_from_b, margin, res.contact)) {
      res.collided = true;
      return true;
    }
    return false;
  }

  // --- distance query (docs/collision.md §11) ---
  std::vector<DistancePair> distance_stack;  // the distance descent's pending node pairs

  // Squared distance from t's vertices to the plane of s when all lie strictly on one side
  // (a lower bound on the faces' squared distance), else 0.
  static double plane_bound2(const TriangleVerts& s, const TriangleVerts& t) {
    const Vec3 n = (s[1] - s[0]).cross(s[2] - s[0]);
    const double nn = n.squaredNorm();
    if (!(nn > 0)) return 0;
    const double d0 = n.dot(t[0] - s[0]), d1 = n.dot(t[1] - s[0]), d2 = n.dot(t[2] - s[0]);
    double m;
    if (d0 > 0 && d1 > 0 && d2 > 0) m = std::min({d0, d1, d2});
    else if (d0 < 0 && d1 < 0 && d2 < 0) m = -std::max({d0, d1, d2});
    else return 0;
    return m * m / nn;
  }

  // Squared gap of the triangles' projections on the line of their centroids (a lower bound on
  // their squared distance), 0 when the projections overlap. Coordinates relative to s[0], so the
  // rounding scales with the triangles and their distance, not with their place.
  static double centre_line_bound2(const TriangleVerts& s, const TriangleVerts& t) {
    const Vec3 t0 = t[0] - s[0], t1 = t[1] - s[0], t2 = t[2] - s[0];
    const Vec3 s1 = s[1] - s[0], s2 = s[2] - s[0];
    const Vec3 u = t0 + t1 + t2 - s1 - s2;  // 3 (centroid of t - centroid of s)
    const double hi_s = std::max({0.0, u.dot(s1), u.dot(s2)});
    const double lo_t = std::min({u.dot(t0), u.dot(t1), u.dot(t2)});
    const double g = lo_t - hi_s, uu = u.squaredNorm();
    return g > 0 && uu > 0 ? g * g / uu : 0.0;
  }

  // One leaf's world faces and the union of their boxes.
  struct LeafFaces {
    std::array<const WorldFace*, kDistanceLeafFaces> w;
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  };
  static LeafFaces leaf_faces(Body& body, const std::uint32_t* faces, std::uint32_t count) {
    LeafFaces l;
    for (std::uint32_t i = 0; i < count; ++i) {
      l.w[i] = &world_face(body, faces[i]);
      l.lo = l.lo.cwiseMin(l.w[i]->lo);
      l.hi = l.hi.cwiseMax(l.w[i]->hi);
    }
    return l;
  }

  // A pair of leaves of the distance trees (the bodies are known apart: no face pair meets).
  // First the gap of both leaves' vertices along the line between their world boxes' centres:
  // the support of each face on that line is one pass over its three vertices, and the gaps of
  // the leaves, of an A face and B's leaf, and of two faces are then a subtraction each (in
  // case (a) of bench_collision_fcl it rules out 70 % of the leaf pairs the node bounds let
  // through). Then each face pair whose world boxes, centroid line and planes' bounds are nearer
  // than `best` is measured. Leaves hold at most kDistanceLeafFaces faces (the engine's trees
  // are built so).
  void distance_leaf_pair(Body& a, Body& b, const DistanceNode& x, const DistanceNode& y, double& best,
                          DistanceResult& res) {
    const std::uint32_t* fas = a.distance_tree->faces.data() + x.first;
    const std::uint32_t* fbs = b.distance_tree->faces.data() + y.first;
    const std::uint32_t na = x.count(), nb = y.count();
    const LeafFaces la = leaf_faces(a, fas, na), lb = leaf_faces(b, fbs, nb);
    // Supports on n, the line of the boxes' centres (any direction gives a lower bound: the
    // leaves' vertices project apart by at least their gap), over coordinates relative to o, the
    // centre of both boxes, so that the rounding scales with the leaves and their distance
    // (|v - o| <= r), not with their place: each support is within 5 u |n| r of its exact
    // value (the subtraction and the dot product), so 1e-14 |n| r covers both sides with room;
    // a relative 1e-12 covers the products with best. A NaN anywhere compares false: nothing
    // is skipped.
    const Vec3 lo = la.lo.cwiseMin(lb.lo), hi = la.hi.cwiseMax(lb.hi);
    const Vec3 o = 0.5 * (lo + hi);
    const Vec3 n = (lb.lo + lb.hi) - (la.lo + la.hi);
    const double nn = n.norm(), slack = 1e-14 * nn * 0.5 * (hi - lo).norm();
    const auto along = [&](const TriangleVerts& t) {
      return std::array<double, 3>{n.dot(t[0] - o), n.dot(t[1] - o), n.dot(t[2] - o)};
    };
    std::array<double, kDistanceLeafFaces> top_a, low_b;  // A faces' highest, B faces' lowest on n
    double sa = -INFINITY, sb = INFINITY;
    for (std::uint32_t i = 0; i < na; ++i) {
      const auto p = along(la.w[i]->t);
      sa = std::max(sa, top_a[i] = std::max({p[0], p[1], p[2]}));
    }
    for (std::uint32_t j = 0; j < nb; ++j) {
      const auto p = along(lb.w[j]->t);
      sb = std::min(sb, low_b[j] = std::min({p[0], p[1], p[2]}));
    }
    // A gap along n at or past `reach` is at or past best (kept with best).
    double reach = best * nn * (1 + 1e-12) + slack;
    if (sb - sa >= reach) return;
    for (std::uint32_t i = 0; i < na; ++i) {
      const WorldFace& wa = *la.w[i];
      if (sb - top_a[i] >= reach || !(box_distance2(wa.lo, wa.hi, lb.lo, lb.hi) < best * best)) continue;
      for (std::uint32_t j = 0; j < nb; ++j) {
        const WorldFace& wb = *lb.w[j];
        if (low_b[j] - top_a[i] >= reach || !(box_distance2(wa.lo, wa.hi, wb.lo, wb.hi) < best * best)) continue;
        const TriangleVerts &ta = wa.t, &tb = wb.t;
        // The centroid line's and the planes' bounds (rounded: a relative 1e-12 of room, far
        // below the 1e-9 asked of the distance), then the closest points.
        const double b2 = best * best * (1 - 1e-12);
        if (centre_line_bound2(ta, tb) >= b2 || plane_bound2(ta, tb) >= b2 || plane_bound2(tb, ta) >= b2) continue;
        ++res.face_pairs;
        Vec3 pa, pb;
        const double d = std::sqrt(disjoint_triangle_distance2(ta, tb, pa, pb));
        if (d < best) {
          best = d;
          reach = best * nn * (1 + 1e-12) + slack;
          res.status = DistanceStatus::exact;
          res.distance = d;
          res.face_a = fas[i], res.face_b = fbs[j];
          res.point_a = pa, res.point_b = pb;
        }
      }
    }
  }

  DistanceResult distance_pair(BodyId ia, BodyId ib, const DistanceRequest& req) {
    const double upper = req.upper_mm;
    DistanceResult res;
    res.body_a = ia, res.body_b = ib;
    res.guess = req.guess;  // kept for the next request unless the hull bound finds a better one
    Body& a = bodies[ia];
    Body& b = bodies[ib];
    const double margin = relative_margin(a.container, a.pose, b.container, b.pose);
    // Step 2's bounds: the vertex spheres and the world minimax boxes.
    const double spheres =
        (world_sphere_centre(a) - world_sphere_centre(b)).norm() - a.container.radius - b.container.radius;
    const double boxes = std::sqrt(box_distance2(world_box(a).lo, world_box(a).hi, world_box(b).lo, world_box(b).hi));
    double lb = std::max(spheres, boxes) - 2 * margin;
    if (lb >= upper) {
      res.distance = lb;
      return res;
    }
    // The oriented containers, each mapped into the other's frame as an axis-aligned box (the
    // bound of the descent's root node pair, without the voxel grids): tighter than the world
    // boxes for rotated bodies, so a pair that is apart by its containers builds no grid.
    const Pose a_from_b = relative_pose(a.pose, b.pose);
    const DistanceNodeTest nt(a_from_b, 2 * margin);
    const Vec3 ha = 0.5 * a.container.size, hb = 0.5 * b.container.size;
    lb = std::max(lb, nt.lower_bound(a.container.origin + ha, ha, b.container.origin + hb, hb));
    // Then the convex hulls' separating-plane bound (small bodies: a pass over the vertices per
    // direction), still without grids: interlocked links whose containers overlap are usually
    // apart by their hulls.
    // Shell by shell when the bodies have a few (the built-in links are boxes and cylinders side
    // by side). A bound reaching `prove` answers: at the cut-off, or at exact_below_mm when the
    // caller needs the distance only below it (the hulls still go on up to the cut-off: a caller
    // keeping the bound, as the continuous checker's anchors, gets a better one for little).
    const double prove = std::min(upper, req.exact_below_mm);
    if (lb < upper && std::isfinite(upper) && a.mesh().vertices.size() <= kHullGapVertices &&
        b.mesh().vertices.size() <= kHullGapVertices) {
      for (Body* x : {&a, &b})
        if (!x->hull_parts) x->hull_parts = std::make_unique<HullParts>(hull_parts_of(x->mesh()));
      const std::size_t shell_pairs = a.hull_parts->count() * b.hull_parts->count();
      if (shell_pairs > 1 && shell_pairs <= kHullPartPairs)
        lb = std::max(lb, parts_gap(*a.hull_parts, *b.hull_parts, a_from_b, 2 * margin, kHullGapEnough * upper, prove,
                                    &res.guess));
      else
        lb = std::max(lb, hull_gap(a.mesh().vertices, b.mesh().vertices, a_from_b, 2 * margin, kHullGapEnough * upper,
                                   kHullGapIterations, upper, &res.guess));
    }
    if (lb >= prove) {
      res.distance = lb;
      return res;
    }
    // Contact first: the four steps at clearance 0 (exact face test, containment) say whether
    // there is a distance at all, usually in a few microseconds; the search below then only
    // measures disjoint faces.
    const double c = clearance;
    clearance = 0;
    QueryResult q;
    const bool hit = test_pair(ia, ib, q);
    clearance = c;
    if (hit) {
      res.status = DistanceStatus::contact;
      res.kind = q.contact.kind;
      res.distance = 0;
      res.face_a = q.contact.face_a, res.face_b = q.contact.face_b;
      res.point_a = res.point_b = q.contact.point;
      return res;
    }
    // The search reads faces and the distance trees only (the voxel grids are step 3's).
    for (Body* x : {&a, &b}) {
      prepare_faces(*x);
      if (!x->distance_tree) x->distance_tree = std::make_unique<DistanceTree>(build_distance_tree(x->mesh()));
    }
    double best = upper;
    descend_distance_tree(*a.distance_tree, *b.distance_tree, DistanceBound(a_from_b, 2 * margin), best,
                          distance_stack, res.node_pairs, [&](const DistanceNode& x, const DistanceNode& y) {
                            distance_leaf_pair(a, b, x, y, best, res);
                          });
    if (res.status != DistanceStatus::exact) res.distance = upper;  // nothing nearer than the cut-off
    return res;
  }
};

Engine::Engine() : impl_(std::make_unique<Impl>()) {}
Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

BodyId Engine::add_body(BodyDef def) {
  Body b;
  b.def = std::move(def);
  const Polyhedron& mesh = b.mesh();
  for (const Vec3& v : mesh.vertices)
    if (!v.allFinite()) throw std::invalid_argument("collision body '" + b.def.name + "' has a non-finite vertex");
  for (const Triangle& t : mesh.triangles)
    for (const std::uint32_t i : t)
      if (i >= mesh.vertices.size())
        throw std::invalid_argument("collision body '" + b.def.name + "' has a triangle index out of range");
  const auto id = static_cast<BodyId>(impl_->bodies.size());
  b.container = make_container(mesh.vertices);
  b.closed = is_closed(mesh);
  b.halvings = def.halvings == kAutoHalvings ? auto_halvings(mesh) : std::clamp(def.halvings, 0, kMaxHalvings);
  b.vertex_pages.resize((mesh.vertices.size() + kVertexPage - 1) / kVertexPage);
  if (mesh.triangles.size() <= kEagerFaces)
    for (auto& page : b.vertex_pages) page = std::make_unique<VertexPage>();
  impl_->bodies.push_back(std::move(b));
  impl_->participation.resize(impl_->bodies.size());
  // Pair counts kept up to date pair by pair: recounting all pairs per body added was
  // quadratic in a cell of many objects. A static body pairs only with the bodies that may move
  // (static-static pairs are never tested), so 10^5 static objects cost 10^5 * moving, not 10^10.
  impl_->pair_count.push_back(0);
  auto pair_with = [&](BodyId other) {
    if (Impl::never_tested(impl_->bodies[other], impl_->bodies[id])) return;
    impl_->participation.set(other, id, true);
    ++impl_->pair_count[other];
    ++impl_->pair_count[id];
  };
  if (impl_->bodies[id].def.is_static) {
    for (const BodyId other : impl_->not_static) pair_with(other);
  } else {
    for (BodyId other = 0; other < id; ++other) pair_with(other);
    impl_->not_static.push_back(id);
  }
  return id;
}

std::size_t Engine::body_count() const { return impl_->bodies.size(); }
const std::string& Engine::body_name(BodyId id) const { return impl_->bodies.at(id).def.name; }
bool Engine::body_closed(BodyId id) const { return impl_->bodies.at(id).closed; }
int Engine::body_halvings(BodyId id) const { return impl_->bodies.at(id).halvings; }
bool Engine::body_preprocessed(BodyId id) const { return impl_->bodies.at(id).grid.has_value(); }
std::span<const BodyPair> Engine::enabled_pairs() const { return impl_->participation.pairs(); }

void Engine::set_pair_enabled(BodyId a, BodyId b, bool enabled) {
  if (a == b || a >= body_count() || b >= body_count()) return;
  // Pairs inside one rigid group and static-static pairs are never tested (docs/collision-method.md §1).
  if (enabled && Impl::never_tested(impl_->bodies[a], impl_->bodies[b])) return;
  if (impl_->participation.enabled(a, b) == enabled) return;
  impl_->participation.set(a, b, enabled);
  for (const BodyId k : {a, b}) {
    if (enabled) ++impl_->pair_count[k];
    else --impl_->pair_count[k];
  }
}
bool Engine::pair_enabled(BodyId a, BodyId b) const { return impl_->participation.enabled(a, b); }
bool Engine::has_enabled_pairs() const { return !impl_->participation.pairs().empty(); }

void Engine::set_default_clearance(double clearance_mm) { impl_->default_clearance = clearance_mm; }

void Engine::set_pose(BodyId id, const Pose& local_to_world) {
  Body& b = impl_->bodies.at(id);
  b.pose = local_to_world;
  ++b.version;
}

Engine::PlacedBounds Engine::placed_bounds(BodyId id) {
  Body& b = impl_->bodies.at(id);
  const Box& box = impl_->world_box(b);
  return {box.lo, box.hi, impl_->world_sphere_centre(b), b.container.radius, margin_share(b.container, b.pose)};
}

void Engine::query(const QueryRequest& req, QueryResult& res) {
  res.clear();
  Impl& s = *impl_;
  s.clearance = req.clearance_mm > 0 ? req.clearance_mm : 0.0;
  // Calls f(a, b) for each requested pair (a < b) until it returns true.
  auto each_pair = [&](auto&& f) {
    if (!req.pairs) {
      for (const BodyPair& p : s.participation.pairs())
        if (f(p.a, p.b)) return;
      return;
    }
    for (BodyPair p : *req.pairs) {
      if (p.a > p.b) std::swap(p.a, p.b);
      if (p.a == p.b || p.b >= body_count() || !s.participation.enabled(p.a, p.b)) continue;
      if (f(p.a, p.b)) return;
    }
  };
  if (!req.gaps) {  // the contact query of every checked pose: nothing else in the loop
    if (req.contact)
      each_pair([&](BodyId a, BodyId b) {
        ++res.counts.pairs_enabled;
        return s.test_pair(a, b, res);
      });
    return;
  }
  each_pair([&](BodyId a, BodyId b) {
    const double margin = s.margin_of(a, b);  // once for both
    res.gaps.push_back(s.pair_gap(a, b, margin));
    if (req.contact && !res.collided) {
      ++res.counts.pairs_enabled;
      s.test_pair(a, b, margin, res);
    }
    return false;
  });
}

QueryResult Engine::query(const QueryRequest& req) {
  QueryResult res;
  query(req, res);
  return res;
}

QueryResult Engine::check() { return query({.clearance_mm = impl_->default_clearance}); }

QueryResult Engine::check_pairs(std::span<const BodyPair> pairs) {
  return query({.clearance_mm = impl_->default_clearance, .pairs = pairs});
}

DistanceResult Engine::distance(BodyId a, BodyId b, const DistanceRequest& request) {
  if (a >= body_count() || b >= body_count() || a == b)
    throw std::invalid_argument("Engine::distance: two different bodies of the engine");
  return impl_->distance_pair(a, b, request);
}

DistanceResult brute_force_distance(const Polyhedron& a, const Pose& pose_a, const Polyhedron& b, const Pose& pose_b) {
  std::vector<Vec3> wa, wb;
  transform_vertices(a.vertices, pose_a, wa);
  transform_vertices(b.vertices, pose_b, wb);
  struct Face {
    TriangleVerts t;
    Vec3 lo, hi;
  };
  auto faces = [](const std::vector<Vec3>& w, const Polyhedron& m) {
    std::vector<Face> f;
    for (const Triangle& tri : m.triangles) {
      const TriangleVerts t = triangle_at(w, tri);
      f.push_back({t, t[0].cwiseMin(t[1]).cwiseMin(t[2]), t[0].cwiseMax(t[1]).cwiseMax(t[2])});
    }
    return f;
  };
  const std::vector<Face> fa = faces(wa, a), fb = faces(wb, b);
  DistanceResult res;
  res.distance = INFINITY;
  // The nearest two vertices bound the distance from above (with room for rounding, so the
  // pair that attains it is still measured below).
  double bound2 = INFINITY;
  for (const Vec3& p : wa)
    for (const Vec3& q : wb) bound2 = std::min(bound2, (p - q).squaredNorm());
  bound2 *= 1 + 1e-9;
  for (std::uint32_t i = 0; i < fa.size(); ++i)
    for (std::uint32_t j = 0; j < fb.size(); ++j) {
      // Boxes farther apart than that bound or the best pair so far: the faces cannot be nearer
      // (keeps the reference fast enough for 100,000 cases; min/max do not round).
      const double lb2 = box_distance2(fa[i].lo, fa[i].hi, fb[j].lo, fb[j].hi);
      if (lb2 > bound2 || !(lb2 < res.distance * res.distance)) continue;
      const TriangleVerts &ta = fa[i].t, &tb = fb[j].t;
      if (triangles_intersect(ta, tb)) {
        res.status = DistanceStatus::contact;
        res.distance = 0;
        res.face_a = i, res.face_b = j;
        res.point_a = res.point_b = contact_point(ta, tb);
        return res;
      }
      Vec3 pa, pb;
      const double d = std::sqrt(triangle_closest_points(ta, tb, pa, pb));
      if (d < res.distance) {
        res.status = DistanceStatus::exact;
        res.distance = d;
        res.face_a = i, res.face_b = j;
        res.point_a = pa, res.point_b = pb;
      }
    }
  auto inside = [&](const std::vector<Vec3>& inner_world, const Polyhedron& inner, const std::vector<Vec3>& outer_world,
                    const Polyhedron& outer) {
    if (!is_closed(outer)) return false;
    for (const std::uint32_t v : shell_vertices(inner))
      if (world_point_inside(inner_world[v], outer_world, outer)) {
        res.status = DistanceStatus::contact;
        res.kind = ContactKind::containment;
        res.distance = 0;
        res.face_a = res.face_b = 0;
        res.point_a = res.point_b = inner_world[v];
        return true;
      }
    return false;
  };
  if (inside(wb, b, wa, a) || inside(wa, a, wb, b)) return res;
  return res;
}

bool brute_force_collides(const Polyhedron& a, const Pose& pose_a, const Polyhedron& b, const Pose& pose_b) {
  return brute_force_collides(a, pose_a, b, pose_b, 0.0);
}

bool brute_force_collides(const Polyhedron& a, const Pose& pose_a, const Polyhedron& b, const Pose& pose_b,
                          double clearance) {
  std::vector<Vec3> wa, wb;
  transform_vertices(a.vertices, pose_a, wa);
  transform_vertices(b.vertices, pose_b, wb);
  for (const Triangle& fa : a.triangles)
    for (const Triangle& fb : b.triangles) {
      const TriangleVerts ta = triangle_at(wa, fa), tb = triangle_at(wb, fb);
      if (triangles_intersect(ta, tb)) return true;
      Vec3 pa, pb;
      if (double d = 0; clearance > 0 && triangles_within(ta, tb, clearance, d, pa, pb)) return true;
    }
  if (is_closed(a))
    for (const std::uint32_t v : shell_vertices(b))
      if (world_point_inside(wb[v], wa, a)) return true;
  if (is_closed(b))
    for (const std::uint32_t v : shell_vertices(a))
      if (world_point_inside(wa[v], wb, b)) return true;
  return false;
}

}  // namespace asimov::collision
