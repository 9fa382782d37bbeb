#include "settings.hpp"

#include "errors.hpp"
#include "vplus_words.hpp"
#include "asimov/interpreter/values.hpp"

#include <fmt/format.h>

#include <cmath>

namespace asimov::interpreter {

namespace {

// A V+ switch or parameter asimov does not simulate (dialect §13): the program stops saying why.
[[noreturn]] void refuse(const std::string& name, WordKind kind) {
  const VplusWord* w = vplus_word(name, kind);
  raise(Message::not_supported, w ? vplus_refusal(*w) : name);
}

}  // namespace

bool vplus_setting(const std::string& name, bool is_switch) {
  return vplus_word(name, is_switch ? WordKind::switch_ : WordKind::parameter) != nullptr;
}

double parameter_value(const std::string& name, const Settings& s, const motion::Simulator& sim) {
  if (vplus_setting(name, false)) refuse(name, WordKind::parameter);
  if (name == "HAND.TIME") return s.hand_time_s;
  if (name == "COLLISION.CLEARANCE") return sim.cell().collision.clearance_mm;
  if (name == "NOT.CALIBRATED") return 0;  // no robot uncalibrated: the simulated arm is calibrated
  raise(Message::illegal_value, fmt::format("unknown parameter {}", name));
}

void set_parameter(const std::string& name, double value, Settings& s, motion::Simulator& sim) {
  if (const VplusWord* w = vplus_word(name, WordKind::parameter)) {
    if (w->support == Support::no_effect) return;  // the terminal's: nothing to set
    refuse(name, WordKind::parameter);
  }
  if (!known_parameter(name)) raise(Message::illegal_value, fmt::format("unknown parameter {}", name));
  if (name == "NOT.CALIBRATED") raise(Message::not_supported, "PARAMETER NOT.CALIBRATED = ...: the simulated arm stays calibrated");
  if (!(value >= 0) || !std::isfinite(value))
    raise(Message::illegal_value, fmt::format("{} = {}", name, format_number(value)));
  if (name == "HAND.TIME") s.hand_time_s = value;
  else sim.set_clearance(value);
}

bool known_parameter(const std::string& name) {
  return name == "HAND.TIME" || name == "COLLISION.CLEARANCE" || name == "NOT.CALIBRATED";
}

bool known_switch(const std::string& name) {
  return name == "CP" || name == "COLLISION" || name == "POWER" || name == "DRY.RUN" || name == "SCALE.ACCEL";
}

bool switch_value(const std::string& name, const Settings& s, const motion::Simulator& sim) {
  if (name == "CP") return s.cp;
  if (name == "COLLISION") return sim.cell().collision.enabled;
  if (name == "POWER") return true;  // the simulated arm is powered and calibrated
  if (name == "DRY.RUN") return false;
  if (name == "SCALE.ACCEL") return true;
  if (vplus_setting(name, true)) refuse(name, WordKind::switch_);
  raise(Message::illegal_value, fmt::format("unknown switch {}", name));
}

bool set_switch(const std::string& name, bool on, Settings& s, motion::Simulator& sim) {
  if (name == "CP") s.cp = on, sim.settings().continuous_path = on;
  else if (name == "COLLISION") sim.set_collision_enabled(on);
  else if (name == "POWER") return on;  // ENABLE POWER: it is on already
  else if (name == "SCALE.ACCEL" || name == "DRY.RUN") return false;
  else if (const VplusWord* w = vplus_word(name, WordKind::switch_)) {
    if (w->support == Support::no_effect) return false;  // the terminal's: a warning
    refuse(name, WordKind::switch_);
  } else raise(Message::illegal_value, fmt::format("unknown switch {}", name));
  return true;
}

void request_configuration(ast::Kw word, robots::ConfigurationRequest& r) {
  switch (word) {
    case ast::Kw::righty: r.righty = 1; break;
    case ast::Kw::lefty: r.righty = 0; break;
    case ast::Kw::above: r.above = 1; break;
    case ast::Kw::below: r.above = 0; break;
    case ast::Kw::noflip: r.noflip = 1; break;
    case ast::Kw::flip: r.noflip = 0; break;
    case ast::Kw::single: r.single = true; break;
    case ast::Kw::multiple: r.single = false; break;
    default: break;
  }
}

}  // namespace asimov::interpreter
