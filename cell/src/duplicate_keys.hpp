// Duplicate keys in a cell's YAML. yaml-cpp keeps both entries of `objects: ... objects: ...`
// and node["objects"] answers the first, so a second list of objects (or a second `box:` in an
// object) was ignored without a word. The text is walked once as parser events (aliases are
// not expanded, so the cost is that of the text) and the first repeated key is reported.
#pragma once
#include <optional>
#include <string>

namespace asimov::cell {

struct DuplicateKey {
  std::string key;
  int line = 0, column = 0;        // the repeated key (1-based)
  int first_line = 0;              // where the key was first given
};

// The first key given twice in one map (plain scalar keys; complex keys are compared by
// nothing). The parser's own errors are left to YAML::Load, which reports them.
std::optional<DuplicateKey> first_duplicate_key(const std::string& yaml);

}  // namespace asimov::cell
