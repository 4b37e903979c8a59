// Sets of faces of a mesh (one byte per face: 1 selected) made into regions a canvas or a paste
// can use: no vertex where the selection touches itself, no holes inside.
#pragma once

#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// Whether the selected faces around `v` form more than one fan (the selection touches itself at v).
bool pinched(const TriMesh& mesh, TriMesh::VertexHandle v, const std::vector<char>& selected);

// Deselects the faces around vertices where the selection is pinched, until none is: every
// vertex of the selection then has one fan of selected faces and the selection is a manifold.
// A pinched vertex is a corner of a selected and of an unselected face: `candidates` lists faces
// whose corners include every such vertex (e.g. the smaller of the two sets), so that the cost
// follows the region rather than the mesh, but for a pass over one byte per vertex. Each round
// visits its vertices in increasing order.
void removePinches(const TriMesh& mesh, std::vector<char>& selected,
                   const std::vector<int>& candidateFaces);

// The selected faces, in increasing order.
std::vector<int> selectedFaces(const std::vector<char>& selected);

// The selected faces edge-connected to face `start` (selected), in increasing order.
std::vector<int> connectedFaces(const TriMesh& mesh, int start, const std::vector<char>& selected);

// Selects the unselected faces that the selection encloses: those not edge-connected through
// unselected faces to a boundary of the mesh or to the unselected face `outside` (-1: none).
void fillEnclosed(const TriMesh& mesh, std::vector<char>& selected, int outside);

}  // namespace geobrush
