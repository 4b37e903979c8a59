// The 3D retrieval of GPU texture cloning (gpu-texture-cloning.txt section 3: "the 3D coordinate
// information is retrieved from the preserved vertex offset based on the projection of the painted
// mesh enclosed by target mesh"; specs/alternatives-001-004.md 1.2 "3D retrieval"):
// p_i = X_T(u_i) + lambda h_i d, the draft the paste places instead of a cage warp.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/domain_locator.hpp"

namespace geobrush {

enum class OffsetDirection {
  Plane,    // d = the target view normal n_PT (the target map's origin normal)
  Surface,  // d = the target's angle-weighted vertex normals interpolated at X_T(u)
};

struct LiftOptions {
  OffsetDirection direction = OffsetDirection::Plane;
};

struct LiftResult {
  std::vector<Eigen::Vector3d> points;  // per lifted vertex, in the order asked
  // The lifted vertices (source canvas vertex ids, ascending) whose u lies outside every target
  // canvas triangle: X_T there is extrapolated linearly from the nearest outline triangle.
  std::vector<int> extrapolated;
};

// Lifts the source canvas vertices `vertices`: u_i = source.uv, h_i = (x_i - o_s) . n_s from the
// source map's origin frame, X_T(u) = targetLocator.locate(u).point, lambda = target.scale.
// `targetLocator` must be the locator of `target`. The vertices must be valid source canvas
// vertex ids.
LiftResult liftVertices(const Parameterization& source, const Parameterization& target,
                        const DomainLocator& targetLocator, const std::vector<int>& vertices,
                        const LiftOptions& options);

}  // namespace geobrush
