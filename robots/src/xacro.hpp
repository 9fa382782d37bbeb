// An in-process xacro expander (what the UR and ROS-Industrial description packages use;
// docs/robots.md "xacro descriptions"): lazily evaluated properties with scopes, ${} Python
// expressions with lists, dicts and load_yaml, macros with ^ defaults and block parameters,
// includes, $(find/arg/env/optenv/eval), xacro:if / unless / element / attribute / call.
// Errors throw UrdfError naming file, line and construct.
#pragma once
#include "asimov/robots/package_path.hpp"
#include "urdf_error.hpp"

#include <map>
#include <string>

namespace asimov::robots {

// Hostile input bounds (docs/limits.md).
inline constexpr int kMaxXacroIncludeDepth = 64;
inline constexpr int kMaxXacroMacroDepth = 64;
inline constexpr std::size_t kMaxXacroOutputBytes = 64u << 20;

// The URDF text `path` expands to. `args`: values of $(arg NAME) over the xacro:arg defaults.
std::string expand_xacro(const std::string& path, const PackagePath& packages,
                         const std::map<std::string, std::string>& args);

}  // namespace asimov::robots
