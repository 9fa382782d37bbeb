// Output files (report, trace, replay page, JUnit, updated expected files) are written to a
// temporary name beside the target and renamed over it, so a reader never sees half a file
// and a failed write leaves the old file as it was.
#pragma once
#include <string>

namespace asimov::app {

// Writes `text` to `path` that way; false, with `why` ("cannot write PATH.tmpPID", ...), when
// the file cannot be written (the temporary file is removed).
bool write_file_atomically(const std::string& path, const std::string& text, std::string& why);

}  // namespace asimov::app
