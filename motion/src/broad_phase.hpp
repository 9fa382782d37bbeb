// Broad phase over the bodies that do not move (docs/collision.md §14) [ours]: a bounding-volume
// tree over their world boxes (the engine's step-2 containers, Engine::placed_bounds), asked per
// moving body for the bodies whose gap may be within a radius, and for a lower bound on the gap
// of every other one. World keeps the pairs of a moving body with the bodies the tree returned
// and leaves the others out while the body's motion since stays below that bound less what the
// consumers need (World::broad_refresh).
#pragma once
#include "asimov/collision/engine.hpp"

#include <cstdint>
#include <vector>

namespace asimov::motion {

class StillTree {
 public:
  // The bodies `ids` at the engine's current poses (they must not move while the tree is used).
  void build(collision::Engine& engine, const std::vector<collision::BodyId>& ids);
  bool empty() const { return items_.empty(); }
  // Appends to `near` every body whose gap bound with `k` is <= within_mm; returns the least gap
  // bound of the others (+inf when none).
  double query(const collision::Engine::PlacedBounds& k, double within_mm, std::vector<collision::BodyId>& near) const;

 private:
  struct Item {
    collision::Engine::PlacedBounds b;
    collision::BodyId id = 0;
  };
  struct Node {
    collision::Vec3 lo, hi;
    double magnitude = 0;          // the largest margin share below
    std::uint32_t first = 0, count = 0;  // leaf: items [first, first + count)
    std::uint32_t left = 0, right = 0;   // inner (count == 0): children
  };
  std::uint32_t build_node(std::uint32_t first, std::uint32_t count);
  std::vector<Item> items_;
  std::vector<Node> nodes_;
  mutable std::vector<std::uint32_t> stack_;
};

}  // namespace asimov::motion
