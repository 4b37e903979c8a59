// Meshes that differ in their points alone: a recycled output (Context::recycle) made for one
// mesh takes another's points where their connectivity is the same.
#pragma once

#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// True where `a` and `b` have the same vertices, halfedges and faces, connected the same way and
// with the same status flags (their points aside): copyPoints from one into the other then makes
// it a copy of that one.
bool sameConnectivity(const TriMesh& a, const TriMesh& b);

// Copies every point of `from` into `into`, which has as many vertices.
void copyPoints(const TriMesh& from, TriMesh& into);
// The points of `vertices` alone.
void copyPoints(const TriMesh& from, const std::vector<int>& vertices, TriMesh& into);

}  // namespace geobrush
