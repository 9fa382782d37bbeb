// MoveIt's Semantic Robot Description Format, the parts a simulator uses: <disable_collisions>
// (pairs the pair matrix leaves untested, source SRDF), <group> and <end_effector> names (an end
// effector's parent link is the arm's tool tip when the cell gives no `tip:`). tinyxml2: no DTD,
// no entity expansion (an "XML bomb" cannot grow), 100 element levels at most, the file read
// bounded (collision::kMaxTextFileBytes).
#pragma once
#include "asimov/core/result.hpp"

#include <string>
#include <utility>
#include <vector>

namespace asimov::robots {

struct Srdf {
  struct Pair {
    std::string link1, link2, reason;  // reason: SRDF's own word ("Adjacent", "Never", ...)
    int line = 0;
  };
  struct Group {
    std::string name;
    std::vector<std::string> links;      // <link name>
    std::vector<std::string> joints;     // <joint name>
    std::string chain_base, chain_tip;   // <chain base_link tip_link>
    std::vector<std::string> subgroups;  // <group name> inside a group
    int line = 0;
  };
  struct EndEffector {
    std::string name, group, parent_link, parent_group;
    int line = 0;
  };
  std::string file;
  std::string robot;  // <robot name>
  std::vector<Pair> disabled;             // <disable_collisions>
  std::vector<Pair> enabled;              // <enable_collisions>: wins over the two others
  std::vector<std::pair<std::string, int>> disabled_links;  // <disable_default_collisions link>: all its pairs
  std::vector<Group> groups;
  std::vector<EndEffector> end_effectors;
  std::vector<std::string> warnings;  // "file:line: ..." (unknown elements are ignored, as MoveIt does)
};

// Reads and checks the structure (required attributes, known group and link references within
// the file). Errors: "file:line: message", file and line set.
Result<Srdf> load_srdf(const std::string& path);
Result<Srdf> load_srdf_text(const std::string& xml, const std::string& source_name);

// Every link the SRDF names (disable_collisions, groups, chains, end effectors) must be one of
// `links` (the URDF's link names): else an Error at the naming line.
Result<void> check_srdf_links(const Srdf& srdf, const std::vector<std::string>& links);

// The pairs of `bodies` (URDF link names) the SRDF leaves untested, each once, in the order of
// `bodies` (a before b): <disable_collisions>, and every pair of a <disable_default_collisions>
// link, less the <enable_collisions> pairs.
std::vector<std::pair<std::string, std::string>> srdf_disabled_pairs(const Srdf& srdf, const std::vector<std::string>& bodies);

// The tool tip the SRDF implies: the parent link of its one end effector; empty when it has
// none, or several with different parent links (the cell's `tip:` decides then).
std::string srdf_tip(const Srdf& srdf);

// One line naming the groups and end effectors, for the user ("groups: manipulator (chain
// base_link -> tool0); end effectors: gripper (parent tool0, group hand)").
std::string describe_srdf(const Srdf& srdf);

}  // namespace asimov::robots
