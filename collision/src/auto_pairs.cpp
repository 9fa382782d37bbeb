#include "asimov/collision/auto_pairs.hpp"

#include "asimov/collision/text_file.hpp"
#include "asimov/core/output_file.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

namespace asimov::collision {
namespace {

constexpr const char* kReasonNames[] = {"ENABLED", "RIGID", "ADJACENT", "DEFAULT", "ALWAYS", "NEVER", "USER_IGNORE", "USER_CHECK", "SRDF"};
static_assert(std::size(kReasonNames) == kPairReasonCount);

struct Fnv {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 0x100000001b3ull;
  }
  template <class T>
  void value(const T& v) { bytes(&v, sizeof v); }
  void text(const std::string& s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  void pairs(const std::vector<BodyPair>& ps) {
    std::vector<BodyPair> sorted;
    for (const BodyPair& p : ps) sorted.push_back({std::min(p.a, p.b), std::max(p.a, p.b)});
    std::sort(sorted.begin(), sorted.end());
    value(sorted.size());
    for (const BodyPair& p : sorted) value(p);
  }
};

std::size_t pair_index(std::size_t n, std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  // Row a holds pairs (a, a+1 .. n-1).
  return static_cast<std::size_t>(a) * n - static_cast<std::size_t>(a) * (a + 1) / 2 + (b - a - 1);
}

bool contains(const std::vector<BodyPair>& ps, std::uint32_t a, std::uint32_t b) {
  return std::any_of(ps.begin(), ps.end(), [&](const BodyPair& p) { return (p.a == a && p.b == b) || (p.a == b && p.b == a); });
}

std::string file_name(std::string s) {
  std::replace_if(s.begin(), s.end(), [](char c) { return c == ' ' || c == '\t' || c == '\n'; }, '_');
  return s.empty() ? "_" : s;
}

}  // namespace

const char* to_string(PairReason r) { return kReasonNames[static_cast<int>(r)]; }
bool is_tested(PairReason r) { return r == PairReason::enabled || r == PairReason::user_check; }

const PairEntry& AutoPairs::entry(std::uint32_t a, std::uint32_t b) const {
  if (a == b || std::max(a, b) >= names.size()) throw std::out_of_range("AutoPairs::entry: no such pair");
  return entries[pair_index(names.size(), a, b)];
}

std::uint64_t content_key(const AutoPairsInput& in) {
  Fnv f;
  f.text("asimov-pairs 1");
  f.value(in.meshes.size());
  for (std::size_t i = 0; i < in.meshes.size(); ++i) {
    f.text(i < in.names.size() ? in.names[i] : "");
    f.value(in.meshes[i].vertices.size());
    for (const Vec3& v : in.meshes[i].vertices) f.bytes(v.data(), 3 * sizeof(double));
    f.value(in.meshes[i].triangles.size());
    for (const Triangle& t : in.meshes[i].triangles) f.value(t);
    f.value(i < in.groups.size() ? in.groups[i] : -1);
    f.value(i < in.is_static.size() && in.is_static[i]);
    f.value(i < in.sampled.size() && in.sampled[i]);
  }
  f.pairs(in.adjacent);
  f.pairs(in.srdf);
  f.pairs(in.user_ignore);
  f.pairs(in.user_check);
  f.text(in.pose_source);
  f.value(in.samples);
  f.value(in.batch);
  f.value(in.always_fraction);
  f.value(in.seed);
  f.value(in.clearance_mm);
  return f.h;
}

AutoPairs generate_pairs(const AutoPairsInput& in) {
  const std::size_t n = in.meshes.size();
  auto flag = [](const std::vector<bool>& v, std::size_t i) { return i < v.size() && v[i]; };
  auto group = [&](std::size_t i) { return i < in.groups.size() ? in.groups[i] : -1; };
  AutoPairs out;
  out.key = content_key(in);
  out.seed = in.seed;
  for (std::size_t i = 0; i < n; ++i) out.names.push_back(i < in.names.size() ? in.names[i] : "body" + std::to_string(i));
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = a + 1; b < n; ++b) {
      PairEntry e{.pair = {a, b}};
      if ((group(a) >= 0 && group(a) == group(b)) || (flag(in.is_static, a) && flag(in.is_static, b)))
        e.reason = PairReason::rigid;
      else if (contains(in.adjacent, a, b))
        e.reason = PairReason::adjacent;
      else if (contains(in.srdf, a, b))
        e.reason = PairReason::srdf;
      out.entries.push_back(e);
    }

  // The pairs left to sample: two sampled bodies, no reason yet.
  std::vector<std::size_t> open;
  for (std::size_t k = 0; k < out.entries.size(); ++k) {
    const PairEntry& e = out.entries[k];
    if (e.reason == PairReason::enabled && flag(in.sampled, e.pair.a) && flag(in.sampled, e.pair.b)) open.push_back(k);
  }
  if (!open.empty() && in.pose_default && in.pose_random) {
    Engine engine;
    for (std::size_t i = 0; i < n; ++i)
      engine.add_body({.name = out.names[i], .mesh = in.meshes[i], .halvings = kAutoHalvings});
    std::vector<Pose> poses(n, Pose::Identity());
    QueryResult r;
    auto in_contact = [&](std::size_t k) {
      const BodyPair p = out.entries[k].pair;
      engine.query({.clearance_mm = in.clearance_mm, .pairs = std::span(&p, 1)}, r);
      return r.collided;
    };
    auto place = [&] {
      for (std::size_t i = 0; i < n; ++i) engine.set_pose(static_cast<BodyId>(i), poses[i]);
    };
    // DEFAULT
    in.pose_default(poses);
    place();
    std::vector<std::size_t> still;
    for (const std::size_t k : open) {
      if (in_contact(k)) out.entries[k].reason = PairReason::default_pose;
      else still.push_back(k);
    }
    open.swap(still);
    // ALWAYS (batches until one adds nothing new), then NEVER over all N samples.
    std::mt19937_64 rng(in.seed);
    const std::uint32_t total = static_cast<std::uint32_t>(std::max(in.samples, 0));
    const std::uint32_t batch = static_cast<std::uint32_t>(std::max(in.batch, 1));
    std::vector<char> always(out.entries.size(), 0);
    bool always_settled = false;
    std::uint32_t drawn = 0;
    while (drawn < total || !always_settled) {
      const std::uint32_t end = drawn + batch;
      for (; drawn < end; ++drawn) {
        in.pose_random(rng, poses);
        place();
        for (const std::size_t k : open) out.entries[k].contacts += in_contact(k);
      }
      if (!always_settled) {
        bool added = false;
        for (const std::size_t k : open) {
          const bool now = out.entries[k].contacts >= in.always_fraction * drawn;
          added = added || (now && !always[k]);
          always[k] = now;
        }
        always_settled = !added && drawn > batch;  // a batch after the first added nothing
      }
    }
    out.samples = drawn;
    for (const std::size_t k : open) {
      PairEntry& e = out.entries[k];
      if (e.contacts >= in.always_fraction * drawn) e.reason = PairReason::always;
      else if (e.contacts == 0) e.reason = PairReason::never;
    }
  }
  for (PairEntry& e : out.entries) {
    if (e.reason == PairReason::rigid) continue;
    if (contains(in.user_ignore, e.pair.a, e.pair.b)) e.reason = PairReason::user_ignore;
    else if (contains(in.user_check, e.pair.a, e.pair.b)) e.reason = PairReason::user_check;
  }
  return out;
}

void save_pairs(const AutoPairs& p, const std::string& path) {
  // Through the one output writer: only a regular file is replaced, written beside it and renamed.
  std::ostringstream f;
  char key[32];
  std::snprintf(key, sizeof key, "%016llx", static_cast<unsigned long long>(p.key));
  f << "asimov-pairs 1\nkey " << key << "\nseed " << p.seed << "\nsamples " << p.samples << "\n";
  for (const PairEntry& e : p.entries)
    f << file_name(p.names[e.pair.a]) << ' ' << file_name(p.names[e.pair.b]) << ' ' << to_string(e.reason) << ' '
      << e.contacts << "\n";
  if (const auto written = core::write_output_file(path, f.str()); !written)
    throw std::runtime_error(written.error().message);
}

bool load_pairs(const std::string& path, std::uint64_t key, AutoPairs& out) {
  // Only a regular file is a cache: a FIFO would block the read, a device never end it.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream f(path);
  std::string magic, version, word, hex;
  if (!(f >> magic >> version) || magic != "asimov-pairs" || version != "1") return false;
  if (!(f >> word >> hex) || word != "key" || std::strtoull(hex.c_str(), nullptr, 16) != key) return false;
  AutoPairs p;
  p.key = key;
  if (!(f >> word >> p.seed) || word != "seed" || !(f >> word >> p.samples) || word != "samples") return false;
  std::vector<std::pair<std::string, std::string>> names;
  std::string a, b, reason;
  std::uint32_t contacts = 0;
  std::vector<PairEntry> entries;
  while (f >> a >> b >> reason >> contacts) {
    const auto* it = std::find(std::begin(kReasonNames), std::end(kReasonNames), reason);
    if (it == std::end(kReasonNames)) return false;
    entries.push_back({.pair = {}, .reason = static_cast<PairReason>(it - std::begin(kReasonNames)), .contacts = contacts});
    names.emplace_back(a, b);
  }
  // Rebuild the body list: pairs are in (a, b) order, so the first row names every body.
  std::size_t n = 0;
  while (n * (n - 1) / 2 < entries.size()) ++n;
  if (n * (n - 1) / 2 != entries.size()) return false;
  if (n >= 2) {
    p.names.push_back(names[0].first);
    for (std::size_t j = 0; j + 1 < n; ++j) p.names.push_back(names[j].second);
  }
  std::size_t k = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j) entries[k++].pair = {i, j};
  p.entries = std::move(entries);
  out = std::move(p);
  return true;
}

AutoPairs generate_pairs_cached(const AutoPairsInput& in, const std::string& cache_path, bool* from_cache) {
  const std::uint64_t key = content_key(in);
  AutoPairs p;
  if (load_pairs(cache_path, key, p) && p.names.size() == in.meshes.size()) {
    for (std::size_t i = 0; i < in.names.size() && i < p.names.size(); ++i) p.names[i] = in.names[i];
    if (from_cache) *from_cache = true;
    return p;
  }
  p = generate_pairs(in);
  save_pairs(p, cache_path);
  if (from_cache) *from_cache = false;
  return p;
}

std::string format_pairs(const AutoPairs& p) {
  // Names as a terminal may show them: a name's control characters (escape sequences) as '?'.
  std::vector<std::string> names;
  for (const std::string& s : p.names) names.push_back(printable(s));
  std::size_t w = 4;
  for (const std::string& s : names) w = std::max(w, s.size());
  std::ostringstream o;
  char line[512];
  std::snprintf(line, sizeof line, "%-*s  %-*s  %-11s  %s\n", static_cast<int>(w), "body", static_cast<int>(w), "body",
                "reason", "contacts");
  o << line;
  for (const PairEntry& e : p.entries) {
    std::snprintf(line, sizeof line, "%-*s  %-*s  %-11s  %u/%u\n", static_cast<int>(w), names[e.pair.a].c_str(),
                  static_cast<int>(w), names[e.pair.b].c_str(), to_string(e.reason), e.contacts, p.samples);
    o << line;
  }
  std::size_t tested = 0;
  for (const PairEntry& e : p.entries) tested += is_tested(e.reason);
  o << tested << " of " << p.entries.size() << " pairs tested; " << p.samples << " random poses, seed " << p.seed << "\n";
  return o.str();
}

void apply_pairs(const AutoPairs& p, Engine& engine) {
  for (const PairEntry& e : p.entries) engine.set_pair_enabled(e.pair.a, e.pair.b, is_tested(e.reason));
}

}  // namespace asimov::collision
