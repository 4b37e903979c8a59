#include "signal_fidelity.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace geobrush {

double signalFidelity(const LaplacianSystem& system, const TriMesh& mesh,
                      const std::vector<double>& signal, const SignalFidelityOptions& options) {
  const std::size_t vertices = system.mesh->surface.n_vertices();
  if (mesh.n_vertices() != vertices)
    throw std::invalid_argument("the mesh has " + std::to_string(mesh.n_vertices()) +
                                " vertices, the system's " + std::to_string(vertices));
  if (signal.size() != vertices)
    throw std::invalid_argument("the signal has " + std::to_string(signal.size()) + " values for " +
                                std::to_string(vertices) + " vertices");
  std::vector<std::uint8_t> border(system.vertices.size(), 0);
  for (int i : system.boundary)
    border[std::size_t(i)] = 1;
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < system.vertices.size(); ++i) {
    if (border[i]) continue;
    const int v = system.vertices[i];
    const VertexGeometry geometry = vertexGeometry(mesh, v);
    double g = geometry.laplace.dot(geometry.normal);
    if (options.perArea) g /= geometry.area;
    const double wanted = signal[std::size_t(v)];
    error += (g - wanted) * (g - wanted);
    norm += wanted * wanted;
  }
  return norm > 0.0 ? std::sqrt(error / norm) : 0.0;
}

}  // namespace geobrush
