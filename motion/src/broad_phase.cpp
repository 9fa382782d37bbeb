#include "broad_phase.hpp"

#include "asimov/collision/gap_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asimov::motion {
namespace {
constexpr std::uint32_t kLeafItems = 4;
}  // namespace

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
    const double bound = collision::gap_bound(k, n.lo, n.hi, n.magnitude);
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
      const double b = collision::gap_bound(k, items_[i].b);
      if (b > within_mm) rest = std::min(rest, b);
      else near.push_back(items_[i].id);
    }
  }
  return rest;
}

}  // namespace asimov::motion
