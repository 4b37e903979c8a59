// A region of a mesh, given by its faces, as a mesh of its own.
#pragma once

#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct Submesh {
  TriMesh surface;
  std::vector<int> sourceVertex;  // surface vertex -> mesh vertex, increasing
  std::vector<int> sourceFace;    // surface face -> mesh face, in the order given
  // The first face OpenMesh could not attach to the ones before it (the
  // region is not manifold there), or -1; faces after it are not added.
  int unattachedFace = -1;
};

// Copies `faces` of `mesh` with the vertices they use, renumbered in
// increasing source order. Costs O(F log F) in the region's size plus
// clearing one int per mesh vertex, so it stays cheap on large meshes.
Submesh extractSubmesh(const TriMesh& mesh, const std::vector<int>& faces);

}  // namespace geobrush
