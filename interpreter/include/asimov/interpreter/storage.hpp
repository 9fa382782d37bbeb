// STORE and STOREL (dialect §8): the text of programs as loaded and of the global data
// sections, numbers in shortest round-trip form, written atomically (temporary file in the
// same folder, fsync, rename), so a reader never sees half a file.
#pragma once
#include "asimov/core/result.hpp"
#include "asimov/interpreter/values.hpp"
#include <string>
#include <vector>

namespace asimov::interpreter {

struct Memory;
struct Program;

// One assigned global: a scalar or one array element. LOCAL variables are not globals.
struct GlobalEntry {
  std::string name;      // "x", "$s", "#p", "pal[2]", "m[1,2]"
  std::string base;      // the variable's name without subscript
  Index index{0, 0, 0};  // the element (zeros for a scalar)
  const Value* value = nullptr;
};

// Every assigned global, sorted by name and then numerically by index.
std::vector<GlobalEntry> global_entries(const Memory& memory);

// Shortest text that reads back as the same double ("0.1", "300", "1e-07"); -0 is "0".
std::string format_real(double x);

// The program's lines from `.PROGRAM` to its `.END`, as they were loaded.
std::vector<std::string> program_lines(const Program& program);

// The file STORE writes: the programs (in the order given), then .LOCATIONS, .REALS and
// .STRINGS with all the globals. `locations_only` (STOREL): only .LOCATIONS.
std::string store_text(const Memory& memory, const std::vector<std::string>& programs, bool locations_only);

// Writes `text` to `path` by the one output writer (core::write_output_file): only a regular
// file is replaced (a device, FIFO or folder is refused), a link's target is replaced, through a
// temporary beside it (write, fsync, rename, fsync of the folder). On failure the temporary is
// removed, the target is untouched, and the error names it and the reason
// ("PATH: cannot write: No space left on device").
Result<void> write_file_atomic(const std::string& path, const std::string& text);

}  // namespace asimov::interpreter
