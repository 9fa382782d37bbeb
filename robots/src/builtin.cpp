// The built-in arms by name: the ASIMOV_BUILTIN_ARM rows of arm_families.def.
#include "asimov/robots/builtin.hpp"

#include <string>

namespace asimov::robots {

#define ASIMOV_BUILTIN_ARM(NAME) Robot NAME();
#include "arm_families.def"

namespace {
struct BuiltinArm {
  std::string_view name;
  Robot (*make)();
};
#define ASIMOV_BUILTIN_ARM(NAME) {#NAME, &NAME},
constexpr BuiltinArm kArms[] = {
#include "arm_families.def"
};
}  // namespace

std::optional<Robot> builtin_robot(std::string_view name) {
  for (const BuiltinArm& a : kArms)
    if (a.name == name) return a.make();
  return std::nullopt;
}

const std::string& builtin_robot_names() {
  static const std::string names = [] {
    std::string s;
    for (const BuiltinArm& a : kArms) s += (s.empty() ? "" : ", ") + std::string(a.name);
    return s;
  }();
  return names;
}

}  // namespace asimov::robots
