// Parameterized meshes and regions for the EMD detail transfer suites.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/laplacian.hpp"
#include "geobrush/region.hpp"
#include "geobrush/vertex_fields.hpp"

namespace geobrush::test {

// A canvas over the whole of `mesh` (its source `mesh`, vertices in the mesh's order),
// parameterized by projection onto the two axes: uv = (p . u, p . v), normals u x v.
std::shared_ptr<const Parameterization> projectedParameterization(const MeshPtr& mesh,
                                                                  const Eigen::Vector3d& u,
                                                                  const Eigen::Vector3d& v);

// A region whose target and source vertices are the canvas vertices of `target` and `source`
// with uv inside `inside` (no grid: what the EMD nodes read).
std::shared_ptr<const Region2D> regionWhere(
    const Parameterization& source, const Parameterization& target,
    const std::function<bool(const Eigen::Vector2d&)>& inside);

// The canvas vertex whose uv lies farthest from vertex `from`'s (the first of equals): the centre
// of a region apart from one around `from`.
int farthestInDomain(const Parameterization& param, int from);

// Eq. 1's g on every vertex of `mesh`, from the whole mesh's operator and area-weighted normals.
std::vector<double> wholeMeshSignal(const TriMesh& mesh);

// A region of a real mesh as the EMD nodes make it: bunny_small projected on the xy plane, the
// disc of a tenth of its diagonal around its first vertex, the mesh's signal (emd_signal's field
// g) and the region's system (laplacian_system's).
struct RealMeshRegion {
  MeshPtr mesh;
  std::shared_ptr<const Parameterization> parameterization;
  std::shared_ptr<const VertexFields> signal;
  std::shared_ptr<const LaplacianSystem> system;
};
RealMeshRegion bunnyRegion();

}  // namespace geobrush::test
