// The four steps of Sec. 5.2 on a working copy of the base, exposed for tests. Vertices below
// `loopVertices` are B0's loop: never moved, never removed. Steps 1-3 add vertices at the end and
// mark removed ones deleted; compactBase renumbers.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "geobrush/mesh.hpp"

namespace geobrush {

double edgeLength(const TriMesh& mesh, TriMesh::EdgeHandle e);

// The smallest interior angle over the faces, in degrees (0 for a degenerate face).
double minimumAngleDeg(const TriMesh& mesh);

// Faces whose aspect ratio (aspectRatio) is at most `tau`.
int countNeedles(const TriMesh& mesh, double tau);

// A lower bound on B's vertex count when every edge is split below `target`: boundary edges are
// halved exactly, and no face of area above sqrt(3)/4 target^2 remains (Euler: V = (F + B) / 2 + 1
// for a disc).
double vertexLowerBound(const TriMesh& mesh, double target);

// Step 1 (Eq. 2): splits the longest edge at its midpoint until every edge is shorter than
// `target`; ties to the larger edge index. Throws BaseGrowthError before exceeding maxVertices.
int splitLongEdges(TriMesh& mesh, double target, std::size_t maxVertices);

// Step 2: every cap (an angle above capAngleDeg, shortest edge at least tau times the longest) is
// sliced by splitting its longest edge at the apex's projection; faces in index order, then the
// new ones. At most four slices per face present at the start.
int sliceCaps(TriMesh& mesh, double capAngleDeg, double tau, std::size_t maxVertices);

// Step 3: while a face has an aspect ratio <= tau, collapses its shortest edge into a boundary
// endpoint, else to the midpoint; never a loop vertex, only where OpenMesh's is_collapse_ok
// holds, no face normal flips and no edge reaches maxLength (Eq. 2 keeps holding).
int collapseNeedles(TriMesh& mesh, int loopVertices, double tau, double maxLength);

// The mesh without deleted elements: vertices 0..loopVertices-1 first, bit-identical, then the
// other live vertices in index order; live faces in index order, each from its first halfedge.
TriMesh compactBase(const TriMesh& mesh, int loopVertices);

// Step 4: `iterations` Jacobi umbrella passes (core umbrellaSmooth) over non-boundary vertices;
// a negative count smooths them to rest (umbrellaSmoothToRest).
void smoothInterior(TriMesh& mesh, int iterations);

}  // namespace geobrush
