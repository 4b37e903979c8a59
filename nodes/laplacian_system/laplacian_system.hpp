// The factored system of EMD detail transfer Eqs. 6-8 over a region of a mesh (see
// geobrush::LaplacianSystem): built once per region and mu, so that a new signal costs one
// back-substitution.
#pragma once

#include <vector>

#include "geobrush/laplacian.hpp"

namespace geobrush {

enum class OutsideNeighbours {
  drop,    // the region solved as an open mesh: only its own faces (the paper's)
  anchor,  // every face around it, the fixed outside neighbours moved to the right-hand side
};

struct LaplacianSystemOptions {
  double mu = 0.1;          // the pull towards the original points inside the region
  double muBoundary = 1.0;  // on its border, against the boundary degeneration
  OutsideNeighbours outside = OutsideNeighbours::anchor;
  LaplacianForm form = LaplacianForm::screened;
};

// `vertices`: the region's mesh vertices, ascending and distinct. Throws std::invalid_argument
// for an empty region or a vertex the mesh lacks, std::out_of_range for a mu outside (0, 1e6],
// std::runtime_error when the matrix cannot be factored. `meshHash`: the mesh's geometryHash where
// the caller has it (0: computed here). `whole`: the mesh's meshDifferentials where the caller has
// them (a dab then reads its operator, normals and areas; the system is the same bit for bit).
LaplacianSystem buildLaplacianSystem(const MeshPtr& mesh, const std::vector<int>& vertices,
                                     const LaplacianSystemOptions& options, Hash meshHash = 0,
                                     const MeshDifferentials* whole = nullptr);

}  // namespace geobrush
