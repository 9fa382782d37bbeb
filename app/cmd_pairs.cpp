// `asimov pairs [CELL.yaml]`: the participation matrix generated for a cell as MoveIt's setup
// assistant does (docs/collision-method.md §1, collision/auto_pairs.hpp), with the reason for each pair.
// The bodies, groups and joined pairs come from motion::scene_bodies, as in the simulator.
#include "asimov/cell/cell_loader.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "asimov/collision/auto_pairs.hpp"
#include "asimov/core/output_file.hpp"
#include "asimov/motion/scene.hpp"

#include <cstdlib>
#include <filesystem>
#include <ostream>

namespace asimov::app {
namespace {

// The cache of the built-in cell: $XDG_CACHE_HOME/asimov/, else ~/.cache/asimov/; empty when
// neither variable is set.
std::string default_cell_cache() {
  std::filesystem::path dir;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) dir = x;
  else if (const char* h = std::getenv("HOME"); h && *h) dir = std::filesystem::path(h) / ".cache";
  else return {};
  return (dir / "asimov" / "default-cell.pairs").string();
}

}  // namespace

int pairs_command(const PairsOptions& opt, std::ostream& out, std::ostream& err) {
  // A --cache that may not be written (a device, FIFO, folder, or the cell file itself) is
  // refused before anything is computed; the default cache beside the cell is then only skipped.
  // (A missing folder stays a warning after the matrix is printed, as before.)
  if (!opt.cache.empty()) {
    std::error_code ec;
    const bool present = std::filesystem::exists(std::filesystem::symlink_status(opt.cache, ec));
    auto ok = present ? core::check_output_path(opt.cache) : Result<void>{};
    if (ok) ok = core::check_outputs_apart({{"the cell file", opt.cell}}, {{"--cache", opt.cache}});
    if (!ok) {
      err << "*Cannot write file*  " << ok.error().message << '\n';
      return kExitUsage;
    }
  }
  const auto loaded = cell::load_cell_for_command(opt.cell, err);
  if (!loaded) return kExitUsage;
  const motion::Cell& cell = *loaded;
  const motion::Scene scene = motion::scene_bodies(cell);
  for (const auto& name : scene.unknown_ignored) err << "Warning: collision.ignore names no body: " << name << '\n';
  const collision::AutoPairsInput in = motion::auto_pairs_input(cell, scene, opt.samples);

  std::string cache = opt.cache;
  if (cache.empty() && !opt.no_cache) cache = opt.cell.empty() ? default_cell_cache() : opt.cell + ".pairs";
  collision::AutoPairs pairs;
  // As collision::generate_pairs_cached, but a cache that cannot be written is only a warning.
  if (!cache.empty() && collision::load_pairs(cache, collision::content_key(in), pairs) &&
      pairs.names.size() == in.names.size()) {
    pairs.names = in.names;  // the file has blanks replaced
    out << collision::format_pairs(pairs);
    err << "pairs: read from " << cache << '\n';
    return kExitCompleted;
  }
  pairs = collision::generate_pairs(in);
  out << collision::format_pairs(pairs);
  if (cache.empty()) return kExitCompleted;
  try {
    // Only the built-in cell's cache folder (~/.cache/asimov) is created; a --cache or CELL.yaml
    // folder that does not exist is the user's mistake, reported below, not made.
    const auto dir = std::filesystem::path(cache).parent_path();
    if (opt.cache.empty() && opt.cell.empty() && !dir.empty()) std::filesystem::create_directories(dir);
    collision::save_pairs(pairs, cache);
    err << "pairs: generated, written to " << cache << '\n';
  } catch (const std::exception& e) {
    err << "Warning: cannot write the pair cache: " << e.what() << '\n';
  }
  return kExitCompleted;
}

}  // namespace asimov::app
