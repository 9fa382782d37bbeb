// The one writer of every output file (report, trace, replay page, JUnit, expected files, the
// pair cache, STORE): an output never destroys what it replaces (docs/cli.md "Output files").
// - Only a regular file is replaced. A device, FIFO, socket or folder at the name (or at the end
//   of a symbolic link) is refused before anything is written: `--report /dev/null` as root
//   would have replaced the system's /dev/null with a plain file.
// - A symbolic link is followed: the file it names is replaced, the link stays a link.
// - The text goes to a temporary file beside the real target, reaches the disk (fsync) and is
//   renamed over it, so a reader never sees half a file and a failed write leaves the old one.
// - A failure names the real target and the reason (the errno text).
#pragma once
#include "asimov/core/result.hpp"
#include <string>
#include <string_view>
#include <vector>

namespace asimov::core {

// The file an output to `path` would replace: `path`, or where its symbolic links lead.
std::string output_target(const std::string& path);

// Whether `path` may receive an output: an error ("PATH: is a FIFO, not a regular file; an
// output replaces only a regular file") when something other than a regular file is there, or
// its folder is missing. Nothing is written.
Result<void> check_output_path(const std::string& path);

// Writes `text` to `path` as above (check_output_path first). The mode of a replaced file is kept.
Result<void> write_output_file(const std::string& path, std::string_view text);

// True when `a` and `b` name the same file: the same inode when both exist, else the same
// absolute path once links in their folders are resolved.
bool same_file(const std::string& a, const std::string& b);

// An output that is also an input of the run, or two outputs on one path: the first such
// clash as an error ("--report crash.v2: is the program file (an input of this run)"), for a
// run's named inputs and outputs (empty names are skipped).
struct NamedPath {
  std::string role;  // "--report", "the program file"
  std::string path;
};
Result<void> check_outputs_apart(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs);

}  // namespace asimov::core
