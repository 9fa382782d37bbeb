// `asimov serve`: the studio (docs/studio.md).
#pragma once
#include <iosfwd>
#include <string>

namespace asimov::serve {

struct ServeOptions {
  std::string workspace = ".";     // the one folder files are opened from and saved to
  std::string cell;                // CELL.yaml; empty: the built-in default cell
  std::string address = "127.0.0.1";
  int port = 0;                    // 0: any free port (the URL says which)
  std::string file;                // opened first (in the workspace); empty: the embedded sample
};

// Prints the URL, serves until Ctrl-C or SIGTERM (exit 0); exit 1 when it cannot start.
int serve_command(const ServeOptions& options, std::ostream& out, std::ostream& err);

// The embedded sample program (programs/demo/pick_place.v2 at build time) and its name.
extern const char* const kSampleName;
extern const char* const kSampleText;

}  // namespace asimov::serve
