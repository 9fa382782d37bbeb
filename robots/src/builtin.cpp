#include "asimov/robots/builtin.hpp"

#include "asimov/robots/cobra_s600.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/viper_s650.hpp"

namespace asimov::robots {

std::optional<Robot> builtin_robot(std::string_view name) {
  if (name == "puma560") return puma560();
  if (name == "viper_s650") return viper_s650();
  if (name == "cobra_s600") return cobra_s600();
  return std::nullopt;
}

const std::string& builtin_robot_names() {
  static const std::string names = "puma560, viper_s650, cobra_s600";
  return names;
}

}  // namespace asimov::robots
