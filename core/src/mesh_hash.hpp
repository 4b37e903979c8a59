// The part of a mesh's content hash that is its geometry: what Mesh::contentHash and
// geometryHash (vertex_fields.hpp) both stream.
#pragma once

#include "geobrush/hash.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// Streams the vertex count, the points, the face count and each face's vertex indices.
void hashGeometry(Hasher& hasher, const TriMesh& mesh);

}  // namespace geobrush
