// Cell files (YAML, docs/cell-format.md) to motion::Cell. The built-in default cell is an
// embedded YAML document parsed by the same code, so it cannot drift from the format.
#pragma once
#include "asimov/motion/cell.hpp"
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>

namespace asimov::cell {

// A problem in a cell file; line and column are 1-based, 0 when unknown.
struct CellError : std::runtime_error {
  CellError(const std::string& what, std::string file, int line, int column)
      : std::runtime_error(what), file(std::move(file)), line(line), column(column) {}
  std::string file;
  int line, column;
  std::string format() const;  // "file:line:column: message"
};

// `base_dir` resolves relative file names in the cell (URDF robots, meshes).
motion::Cell load_cell_text(const std::string& yaml, const std::string& source_name,
                           const std::string& base_dir = ".");
motion::Cell load_cell_file(const std::string& path);
motion::Cell default_cell();

// The commands' common front door: the cell at `path` (empty: the default cell). Problems are
// printed to `err` ("*Cell error*  file:line:column: ..."; warnings as "Warning: ...") and an
// empty result means the command should exit with kExitUsage.
std::optional<motion::Cell> load_cell_for_command(const std::string& path, std::ostream& err);
const std::string& default_cell_yaml();

}  // namespace asimov::cell
