// Finding where a point of the parameter domain lies on a parameterized
// canvas: the inverse map E^-1(u) and the local frame there.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "geobrush/canvas.hpp"

namespace geobrush {

struct DomainHit {
  int face = -1;                // canvas surface face whose uv triangle holds u
  Eigen::Vector3d barycentric;  // of u in that triangle (may be outside [0,1] when clamped)
  Eigen::Vector3d point;        // E^-1(u): the barycentric point on the surface
  Eigen::Vector3d normal;       // the parameterization's normals, interpolated, unit
  Eigen::Matrix<double, 3, 2> jacobian;  // d point / d(u, v) on that face
  bool inside = false;                   // false: u is outside every triangle, the nearest was used
  Frame frame() const;                   // normal, u axis along the jacobian's first column
};

// Buckets the canvas triangles of a parameterization in a uniform grid over
// their uv bounding box, so that each query costs O(1) on average.
class DomainLocator {
 public:
  explicit DomainLocator(const Parameterization& parameterization);

  // The triangle holding u; where several do (fold-overs), the first by face
  // index that is not flagged reversed, else the first. Where none does, the
  // triangle on the canvas' outline (a face with a boundary edge) whose boundary
  // edge is nearest to u, with barycentrics extrapolated (inside = false): the
  // outline does not fold in the domain (paper section 3.1), while the triangles
  // of a fold (a handle's arch over its base) may reach past it, and the nearest
  // of those would switch from sheet to sheet between neighbouring points.
  DomainHit locate(const Eigen::Vector2d& u) const;

 private:
  DomainHit hit(int face, const Eigen::Vector3d& barycentric, bool inside) const;
  DomainHit nearestOutside(const Eigen::Vector2d& u, double cellX, double cellY) const;
  std::span<const int> bucket(int i, int j) const;
  Eigen::Vector3d barycentricOf(int face, const Eigen::Vector2d& u) const;

  const Parameterization& param_;
  std::vector<std::array<int, 3>> faces_;
  Eigen::Vector2d corner_;
  double step_ = 1;
  int cellsX_ = 1, cellsY_ = 1;
  std::vector<int> bucketStart_;  // per cell, its first entry in bucketFaces_; one past the end
  std::vector<int> bucketFaces_;
  // Per face, its boundary edges as corner pairs (k, k + 1 mod 3): bit k set. All zero on a
  // canvas without boundary, which then answers from the nearest triangle.
  std::vector<std::uint8_t> outlineEdges_;
};

class Context;
// The locator on the Parameterization of a node's input `port`, derived data (Context::derived)
// that every node asking on the same value shares.
std::shared_ptr<const DomainLocator> derivedLocator(Context& ctx, std::string_view port);

}  // namespace geobrush
