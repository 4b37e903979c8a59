// Snapping a point onto a mesh: shared by the nodes that pick a canvas origin.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <unsupported/Eigen/BVH>

#include <array>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// The point of a mesh nearest to a query point.
struct SurfacePoint {
  int face = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double distance = 0;
};

// Brute force over all faces; ties go to the lowest face index. The mesh must have a face.
SurfacePoint nearestSurfacePoint(const TriMesh& mesh, const Eigen::Vector3d& query);

// nearestSurfacePoint for many queries on one mesh: a bounding-volume hierarchy of its faces
// (Eigen's KdBVH), built once. Gives the same face and point as nearestSurfacePoint, ties
// included.
class SurfaceLocator {
 public:
  // The mesh must have a face; it is copied, not referenced.
  explicit SurfaceLocator(const TriMesh& mesh);
  SurfacePoint nearest(const Eigen::Vector3d& query) const;

 private:
  std::vector<std::array<Eigen::Vector3d, 3>> triangles_;
  Eigen::KdBVH<double, 3, int> tree_;
};

// The closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace geobrush
