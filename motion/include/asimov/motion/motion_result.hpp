// What a motion comes back with (planner refusals, contacts, interruptions): plain data shared
// by the planner, the walker and the Simulator facade.
#pragma once
#include "asimov/collision/types.hpp"
#include "asimov/core/result.hpp"
#include "asimov/robots/robot.hpp"
#include <cstdint>
#include <string>

namespace asimov::motion {

enum class MotionStatus { ok, error, collision, interrupted };

// The one failure value (core/result.hpp): message = VAL text ("*Location out of reach*",
// "*Joint limit exceeded*", ...), detail e.g. "J3 = 231.000 > 225.000"; no file or line (the
// interpreter adds program and step).
using MotionError = asimov::Error;

// Contact time (docs/collision-method.md §6.4): when the checked pose at t_{k+1} collides and the one at
// t_k was found free, the time is bisected on the exact path between them with the pairs that
// collide at t_{k+1}, until time_s - time_free_s <= CollisionSettings::toc_tolerance_s. The arm
// halts at the pose of time_free_s (collision-free); body names, point, faces and joints are
// those of the contact at time_s.
struct CollisionReport {
  std::string body_a, body_b;
  collision::Vec3 point = collision::Vec3::Zero();  // world [mm], on both bodies' surfaces
  double time_s = 0;                                // contact time t_hit [s] (simulated clock)
  double time_free_s = 0;                           // time of the halting pose t_free [s] (= time_s when
                                                    //   the start pose already collides)
  robots::JointVector joints;                       // display [deg] at t_hit
  std::uint32_t face_a = 0, face_b = 0;             // triangle indices in body_a's / body_b's mesh
                                                    //   (0 for a containment contact)
  int step = 0;                                      // program step of the motion instruction
  std::uint32_t id_a = 0, id_b = 0;                 // the bodies' engine ids (the clearance report's pair)
};

// Where an interrupted motion stopped: at its last checked pose (collision-free when checking
// is on), which is also where the simulated clock stopped.
struct InterruptReport {
  double time_s = 0;         // time of the halting pose [s] (simulated clock)
  double path_fraction = 0;  // path parameter there: 0 = start, 1 = target
  robots::JointVector joints;  // display [deg]
  int step = 0;               // program step of the motion instruction
  bool by_condition = false;  // the stop condition (a REACTI) stopped it, not Ctrl-C's flag
  bool waiting = false;       // stopped in a wait (the arm at rest): no motion to resume
};

// When a motion runs on the simulated clock (the report's per-motion durations): start and
// planned duration; blended: it started before the previous motion had stopped (continuous
// path, docs/blending.md), overlapping it from start_s.
struct MotionTiming {
  int step = 0;
  double start_s = 0;
  double duration_s = 0;
  bool blended = false;
};

struct MotionResult {
  MotionStatus status = MotionStatus::ok;
  MotionError error;            // when status == error
  CollisionReport collision;    // when status == collision
  InterruptReport interrupt;    // when status == interrupted
};

}  // namespace asimov::motion
