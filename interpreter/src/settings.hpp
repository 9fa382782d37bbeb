// Settings of dialect §6: PARAMETER name = value / PARAMETER(name), and ENABLE / DISABLE /
// SWITCH(name) (names in upper case; an unknown one is a *Syntax error* at LOAD); and the
// configuration words of §5.
#pragma once
#include "ast.hpp"
#include "asimov/motion/simulator.hpp"
#include <string>

namespace asimov::interpreter {

// What the interpreter keeps between runs (the simulator holds the collision settings).
struct Settings {
  double hand_time_s = motion::kDefaultHandTime;  // PARAMETER HAND.TIME [s]
  bool cp = true;                                 // ENABLE CP: motions blend (docs/blending.md)
  double accel = 100, decel = 100;                // ACCEL acceleration, deceleration [%]
};

double parameter_value(const std::string& name, const Settings& s, const motion::Simulator& sim);
void set_parameter(const std::string& name, double value, Settings& s, motion::Simulator& sim);

// The names PARAMETER and SWITCH / ENABLE / DISABLE accept (the checker reports any other at
// LOAD): HAND.TIME, COLLISION.CLEARANCE; CP, COLLISION, POWER, DRY.RUN, SCALE.ACCEL.
bool known_parameter(const std::string& name);
bool known_switch(const std::string& name);
// A switch (or parameter) of V+ that asimov does not simulate (dialect §13): it loads; reading
// it stops the program saying why, setting it stops or, for the terminal's, warns.
bool vplus_setting(const std::string& name, bool is_switch);

bool switch_value(const std::string& name, const Settings& s, const motion::Simulator& sim);
// False for the switches V+ has and the simulation ignores with a warning (SCALE.ACCEL, §7;
// DISABLE POWER, DRY.RUN). ENABLE POWER does nothing: the simulated arm's power is on.
bool set_switch(const std::string& name, bool on, Settings& s, motion::Simulator& sim);

// RIGHTY, LEFTY, ABOVE, BELOW, FLIP, NOFLIP, SINGLE, MULTIPLE: a request for the next joint
// motions to transformations (dialect §5).
void request_configuration(ast::Kw word, robots::ConfigurationRequest& r);

}  // namespace asimov::interpreter
