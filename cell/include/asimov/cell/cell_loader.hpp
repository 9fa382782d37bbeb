// Cell files (YAML, docs/cell-format.md) to motion::Cell. The built-in default cell is an
// embedded YAML document parsed by the same code, so it cannot drift from the format.
#pragma once
#include "asimov/core/result.hpp"
#include "asimov/motion/cell.hpp"
#include <iosfwd>
#include <optional>
#include <string>

namespace asimov::cell {

// A problem in a cell file is an Error whose message is the sentence, with file, line and
// column (1-based, 0 when unknown). `base_dir` resolves relative file names in the cell (URDF
// robots, meshes).
Result<motion::Cell> load_cell_text(const std::string& yaml, const std::string& source_name,
                                    const std::string& base_dir = ".");
Result<motion::Cell> load_cell_file(const std::string& path);
motion::Cell default_cell();  // the embedded default cell always loads (a test pins it)

// "file:line:column: message" (or "file: message"), printable whatever bytes the file held.
std::string format_cell_error(const Error& e);

// The commands' common front door: the cell at `path` (empty: the default cell). Problems are
// printed to `err` ("*Cell error*  file:line:column: ..."; warnings as "Warning: ...") and an
// empty result means the command should exit with kExitUsage.
std::optional<motion::Cell> load_cell_for_command(const std::string& path, std::ostream& err);
const std::string& default_cell_yaml();

}  // namespace asimov::cell
