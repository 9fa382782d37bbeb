// Cells in tests: one that must load (else a failed test naming the Error), the Error of one that
// must not.
#pragma once
#include "asimov/cell/cell_loader.hpp"
#include "support/result.hpp"

#include <string>

namespace asimov::test {

inline motion::Cell load_cell_text(const std::string& yaml, const std::string& name, const std::string& base = ".") {
  return must(cell::load_cell_text(yaml, name, base));
}
inline motion::Cell load_cell_file(const std::string& path) { return must(cell::load_cell_file(path)); }

// The Error of `yaml` loaded as `name`.
inline Error cell_error(const std::string& yaml, const std::string& name = "bad.yaml") {
  auto cell = cell::load_cell_text(yaml, name);
  if (cell) FAIL("no error for: " << yaml.substr(0, 200));
  return cell.error();
}

}  // namespace asimov::test
