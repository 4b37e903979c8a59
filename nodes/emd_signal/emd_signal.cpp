#include "emd_signal.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "geobrush/laplacian.hpp"

namespace geobrush {

EmdSignal emdSignal(const TriMesh& mesh, const EmdSignalOptions& options) {
  const Eigen::MatrixX3d points = pointMatrix(mesh);
  if (!points.allFinite()) throw std::invalid_argument("the mesh has a non-finite point");
  const Eigen::MatrixX3d laplace = -(cotangentLaplacian(mesh) * points);  // rows: Delta(v_i)
  const std::vector<Eigen::Vector3d> normals = areaWeightedNormals(mesh);
  const Eigen::VectorXd areas = vertexAreas(mesh);
  EmdSignal signal;
  signal.g.resize(mesh.n_vertices());
  signal.area.assign(areas.data(), areas.data() + areas.size());
  for (std::size_t i = 0; i < signal.g.size(); ++i) {
    double g = laplace.row(Eigen::Index(i)).dot(normals[i]);
    if (options.areaNormalize) {
      if (!(areas[Eigen::Index(i)] > 0.0))
        throw std::invalid_argument("vertex " + std::to_string(i) +
                                    " has no area to normalize by (isolated or on degenerate "
                                    "faces only)");
      g /= areas[Eigen::Index(i)];
    }
    signal.g[i] = g;
  }
  return signal;
}

}  // namespace geobrush
