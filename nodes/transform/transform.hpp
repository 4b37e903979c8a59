// Rigid, scaling and mirroring transforms of a mesh about a pivot.
#pragma once

#include <Eigen/Core>

#include <stdexcept>
#include <string>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct TransformOptions {
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  // Euler angles in degrees about the fixed x, y and z axes, applied in that order:
  // R = Rz * Ry * Rx. Whole quarter turns are exact.
  Eigen::Vector3d rotateDegrees = Eigen::Vector3d::Zero();
  // Per-axis scale, applied first; no entry may be 0. Negative entries mirror.
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  // The point that rotation and scale keep fixed.
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
};

// An option that cannot give an invertible transform. `option()` is its graph-file name
// ("translate", "rotate", "scale", "pivot").
class TransformOptionError : public std::invalid_argument {
 public:
  TransformOptionError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// p' = linear * p + offset.
struct AffineTransform {
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

// Rz * Ry * Rx for angles in degrees.
Eigen::Matrix3d eulerRotation(const Eigen::Vector3d& degrees);

// p' = translate + pivot + R * S * (p - pivot) as one affine map. Throws TransformOptionError
// for a zero or non-finite scale entry or a non-finite vector.
AffineTransform affineTransform(const TransformOptions& options);

// The mesh with every point mapped; vertex and face order are kept (so per-vertex data such as
// colours stay valid). A mirroring transform (negative determinant) also reverses every face's
// winding, so an outward-oriented mesh stays outward-oriented. The result carries points and
// faces only: derived attributes such as normals are left for consumers to recompute.
// Throws TransformOptionError (see affineTransform).
TriMesh transformMesh(const TriMesh& mesh, const TransformOptions& options);

}  // namespace geobrush
