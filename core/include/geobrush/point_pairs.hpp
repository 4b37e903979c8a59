// Corresponding points between a hole's border and a template: the pairs (b_i, t_b_i) that
// align the template (ICP) and then warp it onto the border (Freeform surface inpainting,
// sections 4.1-4.2).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

class PointPairs final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.PointPairs";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  // Pair i: the border point b_i and the template vertex t_b_i, in the border's order.
  std::vector<Eigen::Vector3d> border;
  std::vector<int> templateVertex;
};
using PointPairsPtr = std::shared_ptr<const PointPairs>;

}  // namespace geobrush
