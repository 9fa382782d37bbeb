// Targets of the VAL motion instructions (dialect §5), as free functions the interpreter calls
// after finishing the previous motion (so that HERE is the pose at rest):
//
//   MOVE/MOVES/MOVET/MOVEST loc  start_move(loc, straight)           (MOVET: request_hand first)
//   APPRO/APPROS loc, d          start_move(appro_target(loc, d), straight)
//   DEPART/DEPARTS d             start_move(depart_target(here, d), straight)
//   DRAW dx, dy, dz              start_move(draw_target(here, dx, dy, dz), true)
//   ALIGN                        start_move(align_target(here), false)
//   READY                        start_joint_move(ready_target(robot), speed)
//   DRIVE j, change, speed       drive_target(...) + drive_speed(...), then start_joint_move
#pragma once
#include "asimov/motion/location.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/robot.hpp"

namespace asimov::motion {

// loc:TRANS(0,0,-d): d mm back along the target's tool Z (d may be negative).
Location appro_target(const Location& loc, double d);
// HERE:TRANS(0,0,-d).
Location depart_target(const Location& here, double d);
// SHIFT(HERE BY dx,dy,dz): world axes, orientation unchanged.
Location draw_target(const Location& here, double dx, double dy, double dz);
// Same tool point; tool Z turned onto the nearest world axis +-X/+-Y/+-Z (largest |component|,
// ties to Z, then X, then Y) by the smallest rotation (about z x axis). Already aligned: HERE.
Location align_target(const Location& here);
// READY: robots::ready_joints (PUMA: #PPOINT(0,-90,90,0,0,0); URDF arms: their zero pose).
robots::JointVector ready_target(const robots::Robot& robot);

// DRIVE j, change: `current` with joint j (1-based) moved by `change` (deg, or mm). False (and
// `out` untouched) when j is not a joint of the robot or change is not finite.
bool drive_target(const robots::JointVector& current, int joint, double change, robots::JointVector& out);
// DRIVE speed: `speed_pct` % (0 < s <= 100) of the joint maxima x monitor speed; the program
// speed does not apply. A speed outside (0, 100] gives program = 0 (start_joint_move refuses it).
SpeedSettings drive_speed(double monitor_pct, double speed_pct);

// MOVET / MOVEST: the hand opens when h != 0 and closes when h == 0.
HandState movet_hand(double h);

}  // namespace asimov::motion
