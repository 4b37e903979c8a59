// Point insertion to the target density (Freeform surface inpainting, section 5.2): the template
// refined until every point of it lies within delta_min of a vertex, no inserted vertex closer
// than delta_min / 2 to another. On a mesh the "virtual triangles" are its faces: edges longer
// than sqrt(3) delta_min are bisected at their midpoints, longest first, so that each face's
// points lie within delta_min of a corner (its longest edge / sqrt(3) bounds that distance).
#pragma once

#include <stdexcept>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct PointInsertOptions {
  double deltaMin = 0;                  // the target spacing; must be positive
  bool splitBoundary = false;           // off: the boundary keeps its vertices (a weld shares them)
  std::size_t maxVertices = 5'000'000;  // more is refused rather than allocated
};

struct PointInsertResult {
  TriMesh mesh;                // the template's vertices first, in order, then the inserted ones
  std::size_t inserted = 0;    // vertices added
  std::size_t declined = 0;    // midpoints not inserted: within delta_min / 2 of a vertex
  double closestInserted = 0;  // the least distance from an inserted vertex to any other vertex
};

class PointInsertError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws PointInsertError for a non-positive delta_min or when the refinement would pass
// options.maxVertices.
PointInsertResult insertPoints(const TriMesh& mesh, const PointInsertOptions& options);

// The spacing near a hole's border B [ours]: the median length of the edges at B's vertices.
// Throws PointInsertError for an empty border.
double borderSpacing(const TriMesh& mesh, const std::vector<int>& border);

}  // namespace geobrush
