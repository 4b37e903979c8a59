#include "geobrush/rigid_motion.hpp"

#include <cmath>
#include <numbers>

namespace geobrush {

double RigidMotion::angleDegrees() const {
  const Eigen::Vector3d axis(rotation(2, 1) - rotation(1, 2), rotation(0, 2) - rotation(2, 0),
                             rotation(1, 0) - rotation(0, 1));
  return std::atan2(0.5 * axis.norm(), 0.5 * (rotation.trace() - 1)) * 180 / std::numbers::pi;
}

}  // namespace geobrush
