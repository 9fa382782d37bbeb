// The studio's messages (docs/studio.md "Protocol"): one JSON object per WebSocket text message,
// `{"type": ..., "id": N, ...}`. parse_request is the only place client bytes are interpreted,
// so it bounds everything (size, nesting, string lengths) before anything else sees them; the
// fuzz target fuzz/fuzz_studio_message.cpp runs it on arbitrary bytes.
#pragma once
#include "asimov/core/result.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace asimov::serve {

constexpr std::size_t kMaxMessageBytes = 1 << 20;   // one WebSocket message (the server refuses larger)
constexpr std::size_t kMaxTextBytes = 512 * 1024;   // a program's text (check, run, save)
constexpr std::size_t kMaxLineBytes = 4096;         // a monitor command line
constexpr std::size_t kMaxNameBytes = 255;          // a workspace file name
constexpr int kMaxDepth = 4;                        // nesting of arrays and objects

enum class RequestKind {
  check,    // text, file: check's diagnostics
  monitor,  // line: one monitor command, its output
  run,      // text, file, main: run to the end, the report and the replay data
  abort,    // stop the run or monitor command under way
  list,     // the workspace's files
  open,     // file: its text
  save,     // file, text: written whole into the workspace
  replay,   // file: the last run's replay page written into the workspace
  scene,    // the cell at rest (bodies, the arm's first pose)
  debug,    // action, text, file, main, breakpoints, speed: the program debugger on the editor's program
  pause,    // pause the program running under the debugger at its next step or checked pose
};

// What a `debug` request asks (docs/studio.md "Stepping"): start the editor's program stopped
// before its first step, one step over a CALL (SSTEP) or into it (XSTEP), run on to a
// breakpoint or the end (PROCEED; a start when nothing is stopped), end the stopped program
// (ABORT), or only set the breakpoints and show the variables.
enum class DebugAction { start, step, into, go, abort, state };
constexpr std::size_t kMaxBreakpoints = 1000;

struct Request {
  RequestKind kind = RequestKind::check;
  std::int64_t id = 0;   // echoed in the answer (0 when absent)
  std::string text;      // check, run, save
  std::string file;      // check, run, open, save, replay ("" where optional)
  std::string line;      // monitor
  std::string main;      // run, debug: the program to run ("" the first)
  DebugAction action = DebugAction::state;  // debug
  std::vector<int> breakpoints;             // debug: file lines of the editor (at most kMaxBreakpoints)
  double speed = 1;      // debug: live playback speed of the arm (0: as fast as possible; at most 100)
};

// One message, validated: a JSON object with a known "type", an optional integer "id", and the
// string fields that type uses, each within its bound. Other fields are ignored. The error is
// "*Invalid message*" with what is wrong.
Result<Request> parse_request(std::string_view message);

// The deepest nesting of arrays/objects in a JSON text (strings skipped), counted without
// parsing: the parser is not even started on a text deeper than kMaxDepth.
int json_depth(std::string_view text);

const char* kind_name(RequestKind kind);

}  // namespace asimov::serve
