// Output files of the app (report, trace, replay page, JUnit, updated expected files) go through
// the one output writer, core::write_output_file (asimov/core/output_file.hpp): only a regular
// file is replaced, the text is written beside the real target and renamed over it, and a
// failure names the target and the errno text.
#pragma once
#include "asimov/core/result.hpp"
#include <string>

namespace asimov::app {

// core::write_output_file(path, text).
Result<void> write_file_atomically(const std::string& path, const std::string& text);

}  // namespace asimov::app
