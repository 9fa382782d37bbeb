// `asimov run --replay run.html`: one self-contained HTML page that replays the run in 3D
// (three.js + OrbitControls + app/replay/viewer.js inlined; the scene and the frames as JSON with
// base64 typed arrays). Format and asset lookup: app/README.md.
#pragma once
#include "asimov/core/result.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include <nlohmann/json.hpp>
#include <string>

namespace asimov::app {

// Simulated time between replay frames besides the checked poses [s] (Simulator::set_replay).
constexpr double kReplayGridS = 1.0 / 30;

// The viewer files inlined into the page: three.module.min.js, OrbitControls.js, viewer.js.
struct ReplayAssets {
  std::string three, orbit_controls, viewer;
};

// The folder the assets are read from: $ASIMOV_REPLAY_DIR when set, else share/asimov/replay
// beside the executable's folder (BUILD/share/asimov/replay in the build tree,
// PREFIX/share/asimov/replay installed; app/replay/replay.cmake).
std::string replay_asset_dir();
// Reads the three files; the error names the missing file and the fix when one is missing.
Result<ReplayAssets> load_replay_assets();

// The page's data: bodies (meshes in their local frames), the frames (time, step, joints, world
// pose of every moving body), the program lines of the steps and the contact, if any; in a cell
// with parts or devices also `workcell` (parts, their state segments, devices, events) and the
// carried part's pose per frame. `sim` is the simulator after the run, with set_replay() on
// before it.
// `source`: the file's text when the caller has it (the studio); empty: read from `file`. It names
// the steps that are not motions (WAIT, a hand's time, SIGNAL waits): step_lines.
nlohmann::json replay_data(const std::string& file, const motion::Simulator& sim, const interpreter::RunResult& result,
                           const std::string& source = {});

// The source line of each motion step tag, where the tag names one motion instruction of one
// program of `file` unambiguously: {"TAG": {"program", "line", "text"}} (others are left out).

// The HTML page: `data` in a JSON script element, three.js through an import map of data: URLs.
std::string replay_html(const ReplayAssets& assets, const nlohmann::json& data);

// Base64 (RFC 4648, with padding) of raw bytes; the page's typed arrays use it.
std::string base64(const void* bytes, std::size_t size);

}  // namespace asimov::app
