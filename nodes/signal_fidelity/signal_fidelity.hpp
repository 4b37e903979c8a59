// How closely a rebuilt surface carries the signal it was rebuilt from (EMD detail transfer
// Eq. 1 measured back): |g(mesh) - g^| / |g^| over a region off its border, g(mesh) the signal
// Eq. 1 gives on the mesh.
#pragma once

#include <vector>

#include "geobrush/laplacian.hpp"

namespace geobrush {

struct SignalFidelityOptions {
  bool perArea = false;  // g^ is per unit area (emd_signal's area_normalize): g(mesh) / A_i too
};

// Over the vertices of `system`'s region off its border; `mesh` has the system mesh's
// connectivity, `signal` one value per vertex. 0 where g^ is zero there. Throws
// std::invalid_argument for a mesh or signal of another size.
double signalFidelity(const LaplacianSystem& system, const TriMesh& mesh,
                      const std::vector<double>& signal, const SignalFidelityOptions& options);

}  // namespace geobrush
