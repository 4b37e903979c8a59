// The scalar detail signal of EMD detail transfer (Eq. 1): g(v_i) = Delta(v_i) . n_i, with the
// unnormalized cotangent Laplacian and area-weighted vertex normals.
#pragma once

#include <vector>

#include "geobrush/laplacian.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

struct EmdSignalOptions {
  // Divide g by the vertex area A_i: a curvature-like density that does not scale with the
  // mesh's resolution (on a sphere of radius R, g_i is about -4 A_i / R, g_i / A_i about -4 / R).
  bool areaNormalize = false;
};

struct EmdSignal {
  std::vector<double> g;     // per vertex
  std::vector<double> area;  // A_i: the mixed Voronoi area of vertex i
};

// Eq. 1 on every vertex of `mesh`. Throws std::invalid_argument for a non-finite point, and, with
// areaNormalize, for a vertex without area.
EmdSignal emdSignal(const TriMesh& mesh, const EmdSignalOptions& options);
// The same from the mesh's differentials (meshDifferentials(mesh), which a caller may share).
EmdSignal emdSignal(const TriMesh& mesh, const MeshDifferentials& differentials,
                    const EmdSignalOptions& options);

}  // namespace geobrush
