#include "emd_signal.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "geobrush/laplacian.hpp"

namespace geobrush {

EmdSignal emdSignal(const TriMesh& mesh, const EmdSignalOptions& options) {
  return emdSignal(mesh, meshDifferentials(mesh), options);
}

EmdSignal emdSignal(const TriMesh& mesh, const MeshDifferentials& differentials,
                    const EmdSignalOptions& options) {
  const Eigen::MatrixX3d points = pointMatrix(mesh);
  if (!points.allFinite()) throw std::invalid_argument("the mesh has a non-finite point");
  const Eigen::MatrixX3d laplace = -(differentials.laplacian * points);  // rows: Delta(v_i)
  const std::vector<Eigen::Vector3d>& normals = differentials.normals;
  const Eigen::VectorXd& areas = differentials.areas;
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
