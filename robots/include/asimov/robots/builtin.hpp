// The built-in arms by the name a cell gives them (docs/robots.md): puma560, viper_s650,
// cobra_s600.
#pragma once
#include "asimov/robots/robot.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace asimov::robots {

std::optional<Robot> builtin_robot(std::string_view name);
const std::string& builtin_robot_names();  // "puma560, viper_s650, cobra_s600"

}  // namespace asimov::robots
