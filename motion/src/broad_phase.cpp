#include "broad_phase.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace asimov::motion {
namespace {
constexpr std::uint32_t kLeafItems = 4;

// The box distance as collision/src/container_gap.hpp computes it (same operations, same order).
double box_distance(const collision::Vec3& alo, const collision::Vec3& ahi, const collision::Vec3& blo,
                    const collision::Vec3& bhi) {
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max({0.0, alo[i] - bhi[i], blo[i] - ahi[i]});
    sum += d * d;
  }
  return std::sqrt(sum);
}

// At least relative_margin of any pair whose shares sum to at most `shares` (the engine sums the
// four terms in another order: a relative 1e-6 covers that rounding many times over).
double margin(double shares) { return 64 * DBL_EPSILON * shares * (1 + 1e-6); }
}  // namespace

double box_gap_bound(const collision::Engine::PlacedBounds& k, const collision::Vec3& lo, const collision::Vec3& hi,
                     double magnitude) {
  return box_distance(k.lo, k.hi, lo, hi) - margin(k.magnitude + magnitude);
}

double body_gap_bound(const collision::Engine::PlacedBounds& k, const collision::Engine::PlacedBounds& o) {
  const double spheres = (k.centre - o.centre).norm() - k.radius - o.radius;  // as container_gap
  return std::max(box_distance(k.lo, k.hi, o.lo, o.hi), spheres) - margin(k.magnitude + o.magnitude);
}

void StillTree::build(collision::Engine& engine, const std::vector<collision::BodyId>& ids) {
  items_.clear();
  nodes_.clear();
  items_.reserve(ids.size());
  for (const collision::BodyId id : ids) items_.push_back({engine.placed_bounds(id), id});
  if (items_.empty()) return;
  nodes_.reserve(2 * items_.size() / kLeafItems + 2);
  build_node(0, static_cast<std::uint32_t>(items_.size()));
}

// Median split on the longest axis of the box centres (the tree is built once per change of the
// still bodies, so a plain split is enough).
std::uint32_t StillTree::build_node(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t at = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  collision::Vec3 lo = collision::Vec3::Constant(INFINITY), hi = collision::Vec3::Constant(-INFINITY);
  collision::Vec3 clo = lo, chi = hi;
  double magnitude = 0;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const auto& b = items_[i].b;
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
    const collision::Vec3 c = 0.5 * (b.lo + b.hi);
    clo = clo.cwiseMin(c);
    chi = chi.cwiseMax(c);
    magnitude = std::max(magnitude, b.magnitude);
  }
  Node node;
  node.lo = lo;
  node.hi = hi;
  node.magnitude = magnitude;
  if (count <= kLeafItems) {
    node.first = first;
    node.count = count;
    nodes_[at] = node;
    return at;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const std::uint32_t half = count / 2;
  std::nth_element(items_.begin() + first, items_.begin() + first + half, items_.begin() + first + count,
                   [axis](const Item& x, const Item& y) { return x.b.lo[axis] + x.b.hi[axis] < y.b.lo[axis] + y.b.hi[axis]; });
  node.left = build_node(first, half);
  node.right = build_node(first + half, count - half);
  nodes_[at] = node;
  return at;
}

double StillTree::query(const collision::Engine::PlacedBounds& k, double within_mm,
                        std::vector<collision::BodyId>& near) const {
  double rest = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return rest;
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const Node& n = nodes_[stack_.back()];
    stack_.pop_back();
    const double bound = box_gap_bound(k, n.lo, n.hi, n.magnitude);
    // A NaN bound (never from finite boxes) keeps the node: only a bound that is known far prunes.
    if (bound > within_mm) {
      rest = std::min(rest, bound);
      continue;
    }
    if (n.count == 0) {
      stack_.push_back(n.left);
      stack_.push_back(n.right);
      continue;
    }
    for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
      const double b = body_gap_bound(k, items_[i].b);
      if (b > within_mm) rest = std::min(rest, b);
      else near.push_back(items_[i].id);
    }
  }
  return rest;
}

}  // namespace asimov::motion
