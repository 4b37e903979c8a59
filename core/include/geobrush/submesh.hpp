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

struct AppendedFaces {
  int firstVertex = 0;            // the first vertex of `out` that the call added
  std::vector<int> sourceVertex;  // added vertex firstVertex + i -> mesh vertex, increasing
  std::vector<int> vertexInOut;   // mesh vertex -> vertex of `out`, -1 where no face uses it
  std::vector<int> edgeInOut;     // mesh edge -> edge of `out`, -1 where no face uses it
  std::vector<int> faceInOut;     // mesh face -> face of `out`, -1 where not copied
};

// Appends `faces` of `mesh` (each listed once), in that order, with the edges and vertices they
// use in increasing source order, to `out`. The halfedge connectivity is copied from `mesh` rather
// than rebuilt face by face with add_face, which makes copying most of a large mesh several times
// faster; it walks every vertex, edge and face of `mesh` once. Where the
// faces around a vertex form several fans, `out` gets a non-manifold vertex (as add_face would
// refuse to make): callers that need a manifold select faces that form one fan at each vertex.
AppendedFaces appendFaces(TriMesh& out, const TriMesh& mesh, const std::vector<int>& faces);

// Appends more `faces` of `mesh` to `out`, which already holds `joined` (appendFaces' or
// joinFaces' account of other faces of `mesh` in `out`): vertices and edges the two share are
// reused and the boundary between them closes, as if all had been copied at once. New edges and
// vertices come in the order the faces first use them. Costs O(1)
// per new face plus copying the three index maps (none where `joined` is moved in): a large
// unchanging part of a mesh can be copied once and the rest joined to a copy of it. The result
// accounts for both: sourceVertex and firstVertex for the vertices this call added, the maps for
// all. The new faces must not be in `joined`.
AppendedFaces joinFaces(TriMesh& out, const TriMesh& mesh, const std::vector<int>& faces,
                        AppendedFaces joined);

}  // namespace geobrush
