// Step 1 generated automatically, as MoveIt's Setup Assistant does (docs/collision-method.md §1): which
// body pairs to test, with the reason for each. Works on abstract inputs (meshes, rigid
// groups, an adjacency list and a callback that poses the bodies), so it knows nothing about
// robots. The result is cached in a file keyed by a hash of every input.
//
// Reasons, in the order they are decided (the first that applies wins, user overrides last):
//   RIGID        same rigid group or both static: never tested (not an override target)
//   ADJACENT     joined by a joint (the caller's adjacency list)
//   SRDF         disabled by the description's SRDF (<disable_collisions>, the caller's list)
//   DEFAULT      in contact at the default pose
//   ALWAYS       in contact in >= 95 % of random poses (batches of 200 until a batch adds no
//                new pair to the set)
//   NEVER        never in contact over N random poses (N default 10,000; a statistical claim)
//   USER_IGNORE  the user disabled it;  USER_CHECK  the user enabled it (wins over the above)
//   ENABLED      tested
// Sampling applies only to pairs of two `sampled` bodies (a robot's own links and tool);
// robot-cell pairs stay ENABLED unless the user disables them (sampling would hide hazards).
#pragma once
#include "asimov/collision/engine.hpp"

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace asimov::collision {

enum class PairReason : std::uint8_t { enabled, rigid, adjacent, default_pose, always, never, user_ignore, user_check, srdf };
inline constexpr int kPairReasonCount = 9;
const char* to_string(PairReason r);  // "ENABLED", "RIGID", "ADJACENT", "DEFAULT", ...
bool is_tested(PairReason r);         // enabled or user_check

struct AutoPairsInput {
  std::vector<std::string> names;     // per body, for reports and the cache file
  std::vector<Polyhedron> meshes;     // per body, local frame
  std::vector<int> groups;            // per body: rigid group (-1: its own)
  std::vector<bool> is_static;        // per body
  std::vector<bool> sampled;          // per body: its pairs with other sampled bodies are sampled
  std::vector<BodyPair> adjacent;     // joined bodies (either order)
  std::vector<BodyPair> srdf;         // disabled by an SRDF (either order)
  std::vector<BodyPair> user_ignore;  // overrides (either order)
  std::vector<BodyPair> user_check;
  // Poses of every body (world frame) at the default configuration, and at a random one drawn
  // with `rng` (uniform within the joint limits, for a robot). Both write poses[0..n).
  std::function<void(std::vector<Pose>& poses)> pose_default;
  std::function<void(std::mt19937_64& rng, std::vector<Pose>& poses)> pose_random;
  // Anything else that changes what the callbacks return (kinematics, limits, base, tool
  // offset...), as text: it is part of the cache key.
  std::string pose_source;
  int samples = 10000;            // N for NEVER
  int batch = 200;                // ALWAYS batches
  double always_fraction = 0.95;
  std::uint64_t seed = 20260101;  // fixed: the same cell gives the same matrix
  double clearance_mm = 0;        // contact when distance <= clearance
};

struct PairEntry {
  BodyPair pair;                   // a < b
  PairReason reason = PairReason::enabled;
  std::uint32_t contacts = 0;      // random poses in contact (sampled pairs)
};

struct AutoPairs {
  std::uint64_t key = 0;           // content hash of the input
  std::uint64_t seed = 0;
  std::uint32_t samples = 0;       // random poses drawn
  std::vector<std::string> names;
  std::vector<PairEntry> entries;  // every pair a < b, in order
  const PairEntry& entry(std::uint32_t a, std::uint32_t b) const;  // either order
  bool tested(std::uint32_t a, std::uint32_t b) const { return is_tested(entry(a, b).reason); }
};

// 64-bit FNV-1a over every input field (mesh bytes included) except the callbacks.
std::uint64_t content_key(const AutoPairsInput& in);

AutoPairs generate_pairs(const AutoPairsInput& in);

// generate_pairs, unless `cache_path` holds a matrix with the same key (then no pose is
// drawn). A missing, stale or unreadable cache is regenerated and rewritten (temporary file,
// then rename). `from_cache` says which happened.
AutoPairs generate_pairs_cached(const AutoPairsInput& in, const std::string& cache_path, bool* from_cache = nullptr);

// Cache file: "asimov-pairs 1", "key HEX", "seed N", "samples N", then one line per pair:
// "A B REASON CONTACTS" (body names; names have no blanks in the file: blanks become '_').
void save_pairs(const AutoPairs& p, const std::string& path);
bool load_pairs(const std::string& path, std::uint64_t key, AutoPairs& out);

// The matrix as text for `asimov pairs`: one line per pair with its reason and contact count.
std::string format_pairs(const AutoPairs& p);

// Disables in `engine` every pair the matrix does not test (body ids = input indices).
void apply_pairs(const AutoPairs& p, Engine& engine);

}  // namespace asimov::collision
