// The URDF loader's and the xacro expander's internal error: thrown where a problem is found
// (often deep in the XML walk) and returned as an Error by load_urdf / load_urdf_text, the
// layer's public face (docs/design.md "Errors").
#pragma once
#include <stdexcept>
#include <string>

namespace asimov::robots {

// what() = "file:line: message" (line 0: no line known).
class UrdfError : public std::runtime_error {
 public:
  UrdfError(std::string file, int line, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + message), file_(std::move(file)), line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_ = 0;
};

}  // namespace asimov::robots
