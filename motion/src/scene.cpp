// One scene construction for the simulator and `asimov pairs` (motion/README.md, collision scene).
#include "asimov/motion/scene.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace asimov::motion {

robots::JointVector start_joints(const Cell& cell) {
  return cell.start_joints.size() == cell.robot.joint_count() ? cell.start_joints : robots::ready_joints(cell.robot);
}

Scene scene_bodies(const Cell& cell, bool object_meshes) {
  const auto& robot = cell.robot;
  const int n = robot.joint_count();
  Scene s;
  std::unordered_map<std::string, std::uint32_t> by_name;
  auto add = [&](SceneBody b) {
    by_name.emplace(b.name, static_cast<std::uint32_t>(s.bodies.size()));
    s.bodies.push_back(std::move(b));
  };
  for (const auto& b : robot.bodies) {
    // A follower of an arm joint moves even on the base: a group of its own there.
    const bool still = b.link == 0 && !(b.hand >= 0 && robots::hand_follows_arm(robot, b.hand));
    add({.name = b.name, .mesh = b.mesh, .group = still ? kStaticGroup : b.link == 0 ? -1 : b.link, .is_static = still,
         .robot = true, .link = b.link, .hand = b.hand});
  }
  if (cell.tool_shape) add({.name = "tool", .mesh = *cell.tool_shape, .group = n, .robot = true, .link = n});
  for (std::size_t i = 0; i < cell.objects.size(); ++i)
    add({.name = cell.objects[i].name, .mesh = object_meshes ? cell.objects[i].mesh : collision::Polyhedron{},
         .group = kStaticGroup, .is_static = true, .object = static_cast<int>(i)});
  // Joined parts: adjacent links touch at their joint; the tool is fixed to the flange, next to
  // link n-1 (the J5 body of a 6-axis arm). Bodies of one link share a group anyway.
  const std::uint32_t robot_bodies = static_cast<std::uint32_t>(robot.bodies.size());
  for (std::uint32_t i = 0; i < robot_bodies; ++i)
    for (std::uint32_t j = i + 1; j < robot_bodies; ++j)
      if (std::abs(s.bodies[i].link - s.bodies[j].link) <= 1) s.adjacent.push_back({i, j});
  if (cell.tool_shape)
    for (std::uint32_t i = 0; i < robot_bodies; ++i)
      if (s.bodies[i].link >= n - 1) s.adjacent.push_back({i, robot_bodies});
  const auto resolve = [&](const std::vector<std::pair<std::string, std::string>>& names,
                           std::vector<collision::BodyPair>& out) {
    for (const auto& [a, b] : names) {
      const auto ia = by_name.find(a), ib = by_name.find(b);
      if (ia == by_name.end() || ib == by_name.end()) {
        s.unknown_ignored.push_back(ia == by_name.end() ? a : b);
        continue;
      }
      if (ia->second != ib->second) out.push_back({std::min(ia->second, ib->second), std::max(ia->second, ib->second)});
    }
  };
  resolve(cell.collision.ignore, s.ignored);
  resolve(cell.collision.srdf_disabled, s.srdf);
  resolve(cell.collision.start_contacts, s.start_contacts);
  return s;
}

std::vector<collision::BodyPair> start_contacts(const Cell& cell, const Scene& scene, double clearance_mm) {
  const auto listed = [](const std::vector<collision::BodyPair>& ps, std::uint32_t a, std::uint32_t b) {
    return std::any_of(ps.begin(), ps.end(), [&](const collision::BodyPair& p) { return p.a == a && p.b == b; });
  };
  const auto n = static_cast<std::uint32_t>(scene.bodies.size());
  std::vector<collision::BodyPair> candidates;
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = a + 1; b < n; ++b) {
      const SceneBody &x = scene.bodies[a], &y = scene.bodies[b];
      if (!x.robot || !y.robot || x.group == y.group) continue;
      if (listed(scene.srdf, a, b) || listed(scene.ignored, a, b) || listed(scene.start_contacts, a, b)) continue;
      if (listed(scene.adjacent, a, b) || listed(scene.adjacent, b, a)) continue;
      candidates.push_back({a, b});
    }
  std::vector<collision::BodyPair> found;
  if (candidates.empty()) return found;
  collision::Engine engine;
  std::vector<collision::Pose> frames, poses;
  scene_poses(cell, scene, start_joints(cell), frames, poses);
  std::vector<collision::BodyId> id(n, 0);  // robot bodies only take part
  for (std::uint32_t i = 0; i < n; ++i) {
    const SceneBody& b = scene.bodies[i];
    if (!b.robot) continue;
    id[i] = engine.add_body({.name = b.name, .mesh = b.mesh, .halvings = collision::kAutoHalvings});
    engine.set_pose(id[i], poses[i]);
  }
  collision::QueryResult r;
  for (const collision::BodyPair& p : candidates) {
    const collision::BodyPair q{id[p.a], id[p.b]};
    engine.query({.clearance_mm = clearance_mm, .pairs = std::span(&q, 1)}, r);
    if (r.collided) found.push_back(p);
  }
  return found;
}

void scene_poses(const Cell& cell, const Scene& scene, const robots::JointVector& q, std::vector<collision::Pose>& frames,
                 std::vector<collision::Pose>& poses) {
  robots::link_frames(cell.robot, q, frames);
  poses.resize(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const SceneBody& b = scene.bodies[i];
    poses[i] = b.object >= 0 ? cell.objects[static_cast<std::size_t>(b.object)].pose
                             : cell.base * frames[static_cast<std::size_t>(b.link)];
    if (b.hand >= 0) poses[i] = poses[i] * robots::hand_offset(cell.robot, b.hand, false, q);  // the hand starts open
  }
}

namespace {
// Everything besides the meshes that decides where the bodies are: part of the cache key.
std::string pose_source(const Cell& cell) {
  const auto& r = cell.robot;
  std::ostringstream o;
  o.precision(17);
  auto pose = [&o](const collision::Pose& p) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) o << p.matrix()(i, j) << ' ';
  };
  auto vec = [&o](const robots::JointVector& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) o << v[i] << ' ';
    o << '\n';
  };
  o << "robot " << r.name << " joints " << r.joint_count() << '\n';
  for (const auto& d : r.dh) o << "dh " << d.d << ' ' << d.a << ' ' << d.alpha << '\n';
  for (const auto& j : r.chain) {
    o << "chain " << j.name << ' ' << static_cast<int>(j.type) << ' ' << j.axis.transpose() << ' ';
    pose(j.origin);
    o << '\n';
  }
  o << "flange ";
  pose(r.flange_offset);
  o << "\nmapping ";
  for (const auto& m : r.mapping) o << m.sign << ' ' << m.offset << ' ';
  o << "\nlower ";
  vec(r.lower);
  o << "upper ";
  vec(r.upper);
  o << "base ";
  pose(cell.base);
  o << "\nstart ";
  vec(start_joints(cell));
  for (const auto& obj : cell.objects) {
    o << "object " << obj.name << ' ';
    pose(obj.pose);
    o << '\n';
  }
  return o.str();
}
}  // namespace

collision::AutoPairsInput auto_pairs_input(const Cell& cell, const Scene& scene, int samples) {
  collision::AutoPairsInput in;
  for (const SceneBody& b : scene.bodies) {
    in.names.push_back(b.name);
    in.meshes.push_back(b.mesh);
    in.groups.push_back(b.group);
    in.is_static.push_back(b.is_static);
    in.sampled.push_back(b.robot);
  }
  in.adjacent = scene.adjacent;
  in.srdf = scene.srdf;
  in.user_ignore = scene.ignored;
  in.samples = samples;
  in.clearance_mm = cell.collision.clearance_mm;
  in.pose_source = pose_source(cell);
  in.pose_default = [&cell, &scene, frames = std::vector<collision::Pose>()](std::vector<collision::Pose>& poses) mutable {
    scene_poses(cell, scene, start_joints(cell), frames, poses);
  };
  in.pose_random = [&cell, &scene, frames = std::vector<collision::Pose>(), q = robots::JointVector()](
                       std::mt19937_64& rng, std::vector<collision::Pose>& poses) mutable {
    const auto& r = cell.robot;
    q.resize(r.joint_count());
    std::uniform_real_distribution<double> u(0, 1);
    for (int j = 0; j < r.joint_count(); ++j) q[j] = r.lower[j] + u(rng) * (r.upper[j] - r.lower[j]);
    scene_poses(cell, scene, q, frames, poses);
  };
  return in;
}

}  // namespace asimov::motion
