// Output files (report, trace, replay page, JUnit, updated expected files) are written to a
// temporary name beside the target and renamed over it, so a reader never sees half a file
// and a failed write leaves the old file as it was.
#pragma once
#include "asimov/core/result.hpp"
#include <string>

namespace asimov::app {

// Writes `text` to `path` that way; the error ("cannot write PATH.tmpPID", ...) when the file
// cannot be written (the temporary file is removed).
Result<void> write_file_atomically(const std::string& path, const std::string& text);

}  // namespace asimov::app
