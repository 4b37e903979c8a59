// Moves a mesh so that its area-weighted centroid is at the origin.
#pragma once

#include "geobrush/mesh.hpp"

namespace example {

struct CentreResult {
  geobrush::TriMesh mesh;
  OpenMesh::Vec3d shift;  // what was added to every point
};

CentreResult centreMesh(const geobrush::TriMesh& mesh);

}  // namespace example
