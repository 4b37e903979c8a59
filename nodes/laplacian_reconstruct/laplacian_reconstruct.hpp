// The surface rebuilt from a transferred signal (EMD detail transfer Eqs. 6-8): the region's
// points V^ solve (L^T L + M^2) V^ = L^T T + M^2 V with T = -diag(g^) N - C (plus the original's
// tangential Laplacian coordinates, by default), the system factored
// beforehand (laplacian_system). The minus sign is the erratum of Eq. 6: with Eq. 7's L,
// (L V)_i = -Delta(v_i) while g^ approximates +Delta . n, so Eq. 6 as printed inverts the detail.
#pragma once

#include <vector>

#include "geobrush/laplacian.hpp"

namespace geobrush {

struct ReconstructOptions {
  bool perArea = false;  // the signal is per unit area (emd_signal's area_normalize): times A_i
  // Keep the original's tangential Laplacian coordinates in the target T (ours), so that only
  // the normal component changes; false: T = -diag(g^) N - C alone (the paper's), which also
  // slides the vertices towards a tangentially relaxed mesh.
  bool keepTangential = true;
};

struct ReconstructResult {
  Eigen::MatrixX3d points;  // V^, per unknown of the system
  double maxMove = 0.0;     // the largest |v^_i - v_i|
};

// `signal`: one value per vertex of the system's mesh. Throws std::invalid_argument for a signal
// of the wrong length or with a non-finite value on the region.
ReconstructResult reconstructRegion(const LaplacianSystem& system,
                                    const std::vector<double>& signal,
                                    const ReconstructOptions& options);

// The system's mesh with the region's points replaced; every other point bit-identical.
TriMesh withRegionMoved(const LaplacianSystem& system, const Eigen::MatrixX3d& points);
// The same in place: `mesh` is a copy of the system's mesh, or a mesh this made from one.
void moveRegion(const LaplacianSystem& system, const Eigen::MatrixX3d& points, TriMesh& mesh);

}  // namespace geobrush
