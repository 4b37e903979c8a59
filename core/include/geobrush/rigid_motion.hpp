// A rigid motion x -> R x + t: the alignment of a template to a hole's border and a handle's edit
// (Freeform surface inpainting, sections 4.1 and 5).
#pragma once

#include <Eigen/Core>

namespace geobrush {

struct RigidMotion {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  // The rotation's angle in degrees, in [0, 180].
  double angleDegrees() const;
};

}  // namespace geobrush
