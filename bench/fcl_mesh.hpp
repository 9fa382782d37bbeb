// A mesh as FCL's BVHModel with bounding volumes BV (the FCL peers of bench/ share it).
#pragma once
#include "asimov/collision/polyhedron.hpp"

#include <fcl/geometry/bvh/BVH_model.h>

#include <memory>
#include <vector>

namespace asimov::bench {

template <class BV>
std::shared_ptr<fcl::BVHModel<BV>> fcl_mesh(const collision::Polyhedron& m) {
  auto model = std::make_shared<fcl::BVHModel<BV>>();
  std::vector<fcl::Vector3d> v(m.vertices.begin(), m.vertices.end());
  std::vector<fcl::Triangle> t;
  for (const auto& f : m.triangles) t.emplace_back(f[0], f[1], f[2]);
  model->beginModel();
  model->addSubModel(v, t);
  model->endModel();
  return model;
}

}  // namespace asimov::bench
