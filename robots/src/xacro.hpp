// An in-process xacro expander (the subset robot support packages use; docs/robots.md):
// properties (value and block), ${} expressions, macros with defaults and block parameters,
// includes ($(find pkg), relative), $(arg) with xacro:arg defaults, xacro:if / xacro:unless.
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
