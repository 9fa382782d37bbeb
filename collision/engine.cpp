// The four steps wired together. Per body: preprocessing (container, voxel grid, shells)
// done lazily for bodies in an enabled pair; per pose: world box and world vertices cached
// by pose version, so a static body computes them once. Buffers are members and reused, so
// after the first checks no query allocates.
#include "collision/engine.hpp"

#include "collision/containment.hpp"
#include "collision/face_distance.hpp"
#include "collision/face_pairs.hpp"
#include "collision/face_test.hpp"
#include "collision/interference.hpp"
#include "collision/minimax.hpp"
#include "collision/participation.hpp"
#include "collision/voxel_grid.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

namespace asimov::collision {
namespace {

struct Body {
  BodyDef def;
  Pose pose = Pose::Identity();
  std::uint64_t version = 1;        // bumped by every set_pose
  Container container;              // step 2 basic axes, local
  bool closed = false;              // containment applies (§6.1)
  std::vector<std::uint32_t> shells;// one vertex per shell
  std::optional<VoxelGrid> grid;    // step 3, built on first use
  std::vector<Vec3> world;          // world vertices, valid when world_version == version
  std::uint64_t world_version = 0;
  Box box;                          // world minimax box, valid when box_version == version
  std::uint64_t box_version = 0;
};

TriangleVerts triangle_at(const std::vector<Vec3>& v, const Triangle& t) { return {v[t[0]], v[t[1]], v[t[2]]}; }

// Exact point-in-solid in world coordinates (the reference answer shared with brute force).
bool world_point_inside(const Vec3& w, const std::vector<Vec3>& world, const Polyhedron& mesh) {
  return point_in_solid(w, world, mesh.triangles) != PointClass::outside;
}

}  // namespace

struct Engine::Impl {
  std::vector<Body> bodies;
  Participation participation;
  double clearance = 0;
  std::vector<VoxelPair> voxel_pairs;    // step 3 buffer, reused
  FacePairs face_pairs;                  // step 4 list, buffers reused

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
  const std::vector<Vec3>& world(Body& b) {
    if (b.world_version != b.version) {
      transform_vertices(b.def.mesh.vertices, b.pose, b.world);
      b.world_version = b.version;
    }
    return b.world;
  }
  static void preprocess(Body& b) {
    if (b.grid) return;
    b.grid = build_voxel_grid(b.def.mesh, b.def.halvings);
    b.shells = shell_vertices(b.def.mesh);
  }

  // Is world point w (a vertex of the other body) inside body x? Voxel classes decide when
  // every voxel within the margin agrees; otherwise the exact test in world coordinates.
  bool inside(Body& x, const Vec3& w, double margin) {
    const Vec3 p = x.pose.inverse(Eigen::Isometry) * w;
    const CellRange r = cell_range(*x.grid, Box{p.array() - margin, p.array() + margin});
    if (r.empty()) return false;  // outside the container
    bool all_in = true, all_out = true;
    for (int k = r.lo[2]; k <= r.hi[2]; ++k)
      for (int j = r.lo[1]; j <= r.hi[1]; ++j)
        for (int i = r.lo[0]; i <= r.hi[0]; ++i) {
          const VoxelClass c = x.grid->classes[x.grid->index(i, j, k)];
          all_in = all_in && c == VoxelClass::inside;
          all_out = all_out && c == VoxelClass::outside;
        }
    if (all_in) return true;
    if (all_out) return false;
    return world_point_inside(w, world(x), x.def.mesh);
  }

  bool contained(BodyId ia, BodyId ib, double margin, Contact& c) {
    for (const auto& [outer, inner] : {std::pair{ia, ib}, std::pair{ib, ia}}) {
      Body& o = bodies[outer];
      Body& in = bodies[inner];
      if (!o.closed) continue;
      for (const std::uint32_t v : in.shells) {
        const Vec3& w = world(in)[v];
        if (inside(o, w, margin)) {
          c = Contact{.kind = ContactKind::containment, .body_a = ia, .body_b = ib, .point = w};
          return true;
        }
      }
    }
    return false;
  }

  bool test_pair(BodyId ia, BodyId ib, QueryResult& res) {
    Body& a = bodies[ia];
    Body& b = bodies[ib];
    // Step 2: world minimax boxes.
    const double margin = relative_margin(a.container, a.pose, b.container, b.pose);
    const double grow = clearance + margin;
    if (separated(world_box(a), world_box(b), grow)) return false;
    ++res.counts.pairs_after_minimax;

    // Step 3: voxel pairs.
    preprocess(a);
    preprocess(b);
    collect_voxel_pairs(*a.grid, a.pose, *b.grid, b.pose, grow, voxel_pairs);
    if (!voxel_pairs.empty()) {
      ++res.counts.pairs_after_voxels;
      res.counts.voxel_pairs += voxel_pairs.size();

      // Step 4: unique face pairs, tested in key order in world coordinates.
      face_pairs.start(*a.grid, *b.grid, voxel_pairs);
      const std::vector<Vec3>& wa = world(a);
      const std::vector<Vec3>& wb = world(b);
      std::uint32_t fa = 0, fb = 0;
      while (face_pairs.next(fa, fb)) {
        ++res.counts.face_pairs;
        const TriangleVerts ta = triangle_at(wa, a.def.mesh.triangles[fa]);
        const TriangleVerts tb = triangle_at(wb, b.def.mesh.triangles[fb]);
        if (triangles_intersect(ta, tb)) {
          res.collided = true;
          res.contact = Contact{.body_a = ia, .body_b = ib, .face_a = fa, .face_b = fb, .point = contact_point(ta, tb)};
          return true;
        }
        Vec3 pa, pb;
        if (double d = 0; clearance > 0 && triangles_within(ta, tb, clearance, d, pa, pb)) {
          res.collided = true;
          res.contact = Contact{.kind = ContactKind::clearance, .distance = d, .body_a = ia, .body_b = ib,
                                .face_a = fa, .face_b = fb, .point = 0.5 * (pa + pb)};
          return true;
        }
      }
    }
    // §6.1: no faces meet, but one body may lie inside the other.
    if (contained(ia, ib, margin, res.contact)) {
      res.collided = true;
      return true;
    }
    return false;
  }
};

Engine::Engine() : impl_(std::make_unique<Impl>()) {}
Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

BodyId Engine::add_body(BodyDef def) {
  for (const Vec3& v : def.mesh.vertices)
    if (!v.allFinite()) throw std::invalid_argument("collision body '" + def.name + "' has a non-finite vertex");
  for (const Triangle& t : def.mesh.triangles)
    for (const std::uint32_t i : t)
      if (i >= def.mesh.vertices.size())
        throw std::invalid_argument("collision body '" + def.name + "' has a triangle index out of range");
  const auto id = static_cast<BodyId>(impl_->bodies.size());
  Body b;
  b.container = make_container(def.mesh.vertices);
  b.closed = is_closed(def.mesh);
  b.def = std::move(def);
  impl_->bodies.push_back(std::move(b));
  impl_->participation.resize(impl_->bodies.size());
  for (BodyId other = 0; other < id; ++other)
    if (!Impl::never_tested(impl_->bodies[other], impl_->bodies[id])) impl_->participation.set(other, id, true);
  return id;
}

std::size_t Engine::body_count() const { return impl_->bodies.size(); }
const std::string& Engine::body_name(BodyId id) const { return impl_->bodies.at(id).def.name; }
bool Engine::body_closed(BodyId id) const { return impl_->bodies.at(id).closed; }

void Engine::set_pair_enabled(BodyId a, BodyId b, bool enabled) {
  if (a == b || a >= body_count() || b >= body_count()) return;
  // Pairs inside one rigid group and static-static pairs are never tested (four-step.md §1).
  if (enabled && Impl::never_tested(impl_->bodies[a], impl_->bodies[b])) return;
  impl_->participation.set(a, b, enabled);
}
bool Engine::pair_enabled(BodyId a, BodyId b) const { return impl_->participation.enabled(a, b); }
bool Engine::has_enabled_pairs() const { return !impl_->participation.pairs().empty(); }

void Engine::set_clearance(double clearance_mm) { impl_->clearance = clearance_mm > 0 ? clearance_mm : 0.0; }

void Engine::set_pose(BodyId id, const Pose& local_to_world) {
  Body& b = impl_->bodies.at(id);
  b.pose = local_to_world;
  ++b.version;
}

QueryResult Engine::check() {
  QueryResult res;
  for (const BodyPair& p : impl_->participation.pairs()) {
    ++res.counts.pairs_enabled;
    if (impl_->test_pair(p.a, p.b, res)) return res;
  }
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
