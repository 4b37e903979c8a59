#include "laplacian_reconstruct.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "geobrush/parallel.hpp"

namespace geobrush {

ReconstructResult reconstructRegion(const LaplacianSystem& system,
                                    const std::vector<double>& signal,
                                    const ReconstructOptions& options) {
  if (signal.size() != system.mesh->surface.n_vertices())
    throw std::invalid_argument("the signal has " + std::to_string(signal.size()) + " values for " +
                                std::to_string(system.mesh->surface.n_vertices()) + " vertices");
  const Eigen::Index n = Eigen::Index(system.vertices.size());
  Eigen::MatrixX3d target(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    double g = signal[std::size_t(system.vertices[std::size_t(i)])];
    if (!std::isfinite(g)) throw std::invalid_argument("the signal is not finite on the region");
    if (options.perArea) g *= system.area[i];
    target.row(i) = -g * system.normals.row(i) - system.fixedShare.row(i);
    if (options.keepTangential) target.row(i) += system.tangential.row(i);
  }
  const Eigen::MatrixX3d rhs =
      system.form == LaplacianForm::screened
          ? Eigen::MatrixX3d(target + system.mu.asDiagonal() * system.points)
          : Eigen::MatrixX3d(system.laplacian.transpose() * target +
                             system.mu.cwiseProduct(system.mu).asDiagonal() * system.points);
  // The three coordinates are solved apart, each the same on any thread.
  ReconstructResult result;
  result.points.resize(n, 3);
  parallelBlocks(3, 1, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t c = first; c < last; ++c)
      result.points.col(Eigen::Index(c)) = system.factor->solve(rhs.col(Eigen::Index(c)));
  });
  result.maxMove = (result.points - system.points).rowwise().norm().maxCoeff();
  return result;
}

TriMesh withRegionMoved(const LaplacianSystem& system, const Eigen::MatrixX3d& points) {
  TriMesh moved = system.mesh->surface;
  moveRegion(system, points, moved);
  return moved;
}

void moveRegion(const LaplacianSystem& system, const Eigen::MatrixX3d& points, TriMesh& mesh) {
  for (std::size_t i = 0; i < system.vertices.size(); ++i) {
    const Eigen::Index row = Eigen::Index(i);
    mesh.set_point(TriMesh::VertexHandle(system.vertices[i]),
                   {points(row, 0), points(row, 1), points(row, 2)});
  }
}

}  // namespace geobrush
