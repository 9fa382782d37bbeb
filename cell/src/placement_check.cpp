#include "placement_check.hpp"

#include "asimov/collision/engine.hpp"
#include "asimov/motion/resting.hpp"
#include "asimov/motion/support.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace asimov::cell {
namespace {

struct Box {
  collision::Vec3 lo, hi;
};

Box world_box(const collision::Polyhedron& mesh, const collision::Pose& pose) {
  Box b{collision::Vec3::Constant(1e300), collision::Vec3::Constant(-1e300)};
  for (const auto& v : mesh.vertices) {
    const collision::Vec3 w = pose * v;
    b.lo = b.lo.cwiseMin(w), b.hi = b.hi.cwiseMax(w);
  }
  return b;
}

}  // namespace

std::optional<Misplaced> first_misplaced_part(const motion::Cell& cell) {
  const auto& parts = cell.workcell.parts;
  const auto& feeders = cell.workcell.feeders;
  if (parts.empty() && feeders.empty()) return std::nullopt;
  // Bodies: the objects (conveyors among them), then the parts, then each feeder's part at its
  // feed pose; static among themselves.
  enum class Kind { object, part, feeder };
  struct Body {
    const collision::Polyhedron* mesh;
    collision::Pose pose;
    std::string what;
    Kind kind;
    std::size_t index;
  };
  std::vector<Body> bodies;
  for (std::size_t i = 0; i < cell.objects.size(); ++i)
    bodies.push_back({&cell.objects[i].mesh, cell.objects[i].pose, "object '" + cell.objects[i].name + "'", Kind::object, i});
  for (std::size_t i = 0; i < parts.size(); ++i)
    bodies.push_back({&parts[i].mesh, parts[i].pose, "part '" + parts[i].name + "'", Kind::part, i});
  for (std::size_t i = 0; i < feeders.size(); ++i)
    if (feeders[i].count > 0)
      bodies.push_back({&feeders[i].part.mesh, feeders[i].part.pose, "feeder '" + feeders[i].name + "'", Kind::feeder, i});
  // A feeder's part never meets a part whose origin lies in its spot (the feeder waits until that
  // one left), nor another feeder's whose feed pose lies in its spot or its own in the other's.
  const auto waits = [&](const Body& a, const Body& b) {
    if (a.kind != Kind::feeder && b.kind != Kind::feeder) return false;
    // Objects (conveyors among them) never leave: only a part or a feeder's part is waited for.
    const auto in_spot = [&](const Body& f, const Body& x) {
      return f.kind == Kind::feeder && x.kind != Kind::object && feeders[f.index].spot.contains(x.pose.translation());
    };
    return in_spot(a, b) || in_spot(b, a);
  };
  // Order of report: parts in declaration order, then feeders; of a pair, the later one.
  const auto rank = [&](const Body& b) { return b.kind == Kind::object ? 0 : b.kind == Kind::part ? 1 + b.index : 1 + parts.size() + b.index; };

  // Candidate pairs (a part with anything) from overlapping bounding boxes: sweep along x.
  std::vector<Box> boxes;
  boxes.reserve(bodies.size());
  for (const auto& b : bodies) boxes.push_back(world_box(*b.mesh, b.pose));
  std::vector<std::size_t> order(bodies.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return boxes[a].lo.x() < boxes[b].lo.x(); });
  std::vector<std::pair<std::size_t, std::size_t>> candidates;  // (part body, other body)
  std::vector<std::size_t> active;
  for (const std::size_t i : order) {
    std::erase_if(active, [&](std::size_t k) { return boxes[k].hi.x() < boxes[i].lo.x(); });
    for (const std::size_t k : active) {
      if (bodies[i].kind == Kind::object && bodies[k].kind == Kind::object) continue;
      const bool overlap = (boxes[i].lo.array() <= boxes[k].hi.array()).all() && (boxes[k].lo.array() <= boxes[i].hi.array()).all();
      if (!overlap || waits(bodies[i], bodies[k])) continue;
      // The later declared part (or feeder) is the one reported (placed into what came before it).
      const bool i_later = rank(bodies[i]) > rank(bodies[k]);
      candidates.emplace_back(i_later ? i : k, i_later ? k : i);
    }
    active.push_back(i);
  }
  if (candidates.empty()) return std::nullopt;
  std::sort(candidates.begin(), candidates.end(), [&](const auto& a, const auto& b) {
    const std::size_t ra = rank(bodies[a.first]), rb = rank(bodies[b.first]);
    return ra != rb ? ra < rb : a.second < b.second;
  });

  collision::Engine engine;
  std::vector<collision::BodyId> id(bodies.size());
  std::vector<bool> added(bodies.size(), false);
  const auto add = [&](std::size_t i) {
    if (added[i]) return;
    id[i] = engine.add_body({.name = bodies[i].what, .mesh = {}, .mesh_ref = bodies[i].mesh, .halvings = collision::kAutoHalvings});
    engine.set_pose(id[i], bodies[i].pose);
    added[i] = true;
  };
  for (const auto& [p, o] : candidates) add(p), add(o);
  std::vector<std::size_t> of_id(engine.body_count());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (added[i]) of_id[id[i]] = i;
  const auto normal = [&](collision::BodyId b, std::uint32_t f) -> collision::Vec3 {
    const Body& body = bodies[of_id[b]];
    if (f >= body.mesh->triangles.size()) return collision::Vec3::Zero();
    const auto& t = body.mesh->triangles[f];
    const auto& v = body.mesh->vertices;
    const collision::Vec3 n = body.pose.linear() * (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]);
    const double len = n.norm();
    return len > 0 ? collision::Vec3(n / len) : collision::Vec3::Zero();
  };
  collision::QueryResult r, scratch;
  for (const auto& [p, o] : candidates) {
    const collision::BodyPair pair{id[p], id[o]};
    engine.query({.clearance_mm = 0, .pairs = std::span(&pair, 1)}, r);
    if (!r.collided) continue;
    double tol = motion::resting_tolerance(*bodies[p].mesh);
    if (bodies[o].kind != Kind::object) tol = std::max(tol, motion::resting_tolerance(*bodies[o].mesh));
    // Touching side by side (a row of parts, a part against a fence): coplanar faces may be the
    // only contacts found, whose normals do not separate the pair, so the axes of the world and
    // of the part are tried first, then the contacts' normals as at run time.
    bool apart = false;
    if (r.contact.kind != collision::ContactKind::containment)
      for (int axis = 0; axis < 6 && !apart; ++axis)
        for (const double sign : {1.0, -1.0}) {
          const collision::Vec3 d = sign * (axis < 3 ? collision::Vec3(collision::Vec3::Unit(axis))
                                                     : collision::Vec3(bodies[p].pose.linear().col(axis - 3)));
          collision::Pose shifted = bodies[p].pose;
          shifted.translation() += tol * d;
          engine.set_pose(id[p], shifted);
          engine.query({.clearance_mm = 0, .pairs = std::span(&pair, 1)}, scratch);
          if (!scratch.collided) {
            apart = true;
            break;
          }
        }
    engine.set_pose(id[p], bodies[p].pose);
    if (apart || motion::resting_contact(engine, pair, id[p], bodies[p].pose, tol, r.contact, normal, scratch)) continue;
    const bool feeder = bodies[p].kind == Kind::feeder;
    if (r.contact.kind == collision::ContactKind::containment)
      return Misplaced{bodies[p].index, feeder,
                       feeder ? fmt::format("{} places its parts inside {} (they lie one inside the other); move the "
                                            "feeder's at: onto or beside it", bodies[p].what, bodies[o].what)
                              : fmt::format("{} and {} lie one inside the other at the start; place the part on or beside it",
                                            bodies[p].what, bodies[o].what)};
    return Misplaced{bodies[p].index, feeder,
                     feeder ? fmt::format("{} places its parts sunk into {} (deeper than their resting tolerance of {:.3g} "
                                          "mm); move the feeder's at: onto or beside it", bodies[p].what, bodies[o].what, tol)
                            : fmt::format("{} sinks into {} at the start (deeper than its resting tolerance of {:.3g} mm); "
                                          "place it on or beside it", bodies[p].what, bodies[o].what, tol)};
  }
  return std::nullopt;
}

}  // namespace asimov::cell
