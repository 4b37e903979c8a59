// Snapping a point onto a mesh: shared by the nodes that pick a canvas origin.
#pragma once

#include <Eigen/Core>

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

// The closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace geobrush
