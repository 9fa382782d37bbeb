#pragma once
// Bounded whole-file reads for every loader (programs, cells, URDF, meshes): a directory, a file
// that cannot be opened and one longer than the caller's limit are errors, so `--cell /dev/zero`
// or a URDF that is a folder end with a message instead of reading forever.
#include "asimov/core/result.hpp"

#include <cstddef>
#include <string>
#include <string_view>

namespace asimov::collision {

// Limits, in bytes, the loaders use (docs/limits.md says why these sizes).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{64} << 20;   // programs, cells, URDF
inline constexpr std::size_t kMaxMeshFileBytes = std::size_t{512} << 20;  // STL / OBJ

// The file's bytes, or an Error whose message is the reason without the path ("is a directory,
// not a file", "cannot open the file (...)", "is larger than 16 MiB, ...") and whose file is `path`:
// callers put the path in front in their own words.
Result<std::string> read_file_bounded(const std::string& path, std::size_t max_bytes);

// What stands at `path` for a loader that wants a regular file. A missing name is `missing`; a
// folder, FIFO, device or socket is named as what it is in `not_regular` ("is a FIFO, not a
// regular file"): a FIFO with no writer would block the read forever and a device never end it,
// so these are refused before any open. An empty `not_regular` and !missing: a regular file.
struct InputFile {
  bool missing = false;
  std::string not_regular;  // the reason, without the path
};
InputFile classify_input_file(const std::string& path);

// `text` safe to print on a terminal and in JSON: control characters (C0, DEL, C1: escape
// sequences that would clear or recolour the screen) and bytes that are not valid UTF-8 become
// '?', one per byte, so a caret under a column still lines up; tabs and valid UTF-8 stay.
std::string printable(std::string_view text);

}  // namespace asimov::collision
