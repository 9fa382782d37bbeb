// Scenes shared by the collision benchmarks (bench_collision_fcl, bench_m_sweep): generated
// meshes of stated face counts, fixed-seed random poses, and the PUMA default cell with a
// recorded joint trajectory. Fixed seeds everywhere, so every run sees the same inputs.
#pragma once
#include "asimov/collision/polyhedron.hpp"
#include "asimov/motion/cell.hpp"

#include <cstdint>
#include <vector>

namespace asimov::bench {

using collision::Polyhedron;
using collision::Pose;

// Closed torus about local Z with a bumpy tube (non-convex in two ways): `nu` segments around
// the axis, `nv` around the tube, 2 nu nv triangles, outward orientation.
Polyhedron make_bumpy_torus(double major, double minor, int nu, int nv, double bump = 0.15);

// A closed bumpy torus with about `faces` triangles (exactly 2 nu nv, nu ~ 2 nv) whose size is
// `major` (tube radius major / 3).
Polyhedron make_torus_with_faces(int faces, double major);

// Coal's env/rob benchmark method with our own meshes: env ~2,000 faces (1,000 mm torus),
// rob ~200 faces (150 mm torus).
Polyhedron make_env_mesh();
Polyhedron make_rob_mesh();

// Uniform random rotations (normalised Gaussian quaternions) and translations in +-reach.
std::vector<Pose> random_poses(std::size_t n, double reach, std::uint64_t seed);

// The built-in default cell (cell::default_cell()) and a recorded trajectory: `moves` joint
// moves between random configurations within the joint limits, each sampled at `samples`
// evenly spaced poses (display joint values [deg]).
struct PumaScene {
  motion::Cell cell;
  std::vector<robots::JointVector> trajectory;
};
PumaScene make_puma_scene(int moves = 20, int samples = 500, std::uint64_t seed = 560);

}  // namespace asimov::bench
