// The base surface B from a boundary triangulation B0 (topology-free cut-and-paste, Sec. 5.2):
// edge splitting to the density of Eq. 2, slicing of caps, collapse of needles, umbrella
// smoothing, in this order, with the boundary loop fixed. B keeps cut_paste.hpp's convention:
// vertices 0..n-1 are B0's loop, bit-identical and in order, the other vertices follow, points
// added on the boundary lie on the loop's chords, and the boundary halfedges run i -> i + 1.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct BaseOptimizeOptions {
  double epsilon = 2.0;          // Eq. 2: every edge ends shorter than epsilon * the reference
  double referenceLength = 0.0;  // the reference; 0: l_min, B0's shortest edge (Sec. 5.2)
  double capAngleDeg = 160.0;    // a face with a larger angle that is no needle is a cap
  double aspectThreshold = 0.1;  // tau: needles are collapsed until every aspect ratio exceeds it
  // Jacobi umbrella passes over the interior vertices; negative: to rest (their limit).
  int smoothIterations = -1;
  std::size_t maxVertices = 2000000;  // refuse a density that would need more vertices
};

struct BaseOptimizeResult {
  TriMesh base;
  int loopVertices = 0;            // n: B0's boundary loop, vertices 0..n-1 of `base`
  double referenceLength = 0.0;    // the reference Eq. 2 used
  double targetLength = 0.0;       // epsilon * reference
  int splits = 0;                  // step 1 (and any resplit after smoothing)
  int slices = 0;                  // step 2
  int collapses = 0;               // step 3
  int resplits = 0;                // splits after smoothing, where it lengthened an edge
  int needlesLeft = 0;             // faces whose aspect ratio is still <= tau (collapse refused)
  double minAngleBeforeDeg = 0.0;  // over B0's faces
  double minAngleAfterDeg = 0.0;   // over B's faces
};

// Thrown when the density asked for (epsilon * reference) would exceed options.maxVertices.
class BaseGrowthError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Sec. 5.2's aspect ratio: short side over long side of the smallest rectangle holding the
// triangle with a side on one of its edges. Edges with an obtuse angle at an end need a wider
// rectangle, so the candidates are the edges with no obtuse angle at either end, each giving an
// e x (2 area / e) rectangle of the same, least area; of those the squarest counts (equilateral
// sqrt(3)/2, right isosceles 1, a cap of height h over its longest edge L: h / L; 0 when
// degenerate).
double aspectRatio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// The length of the shortest edge of `mesh` (l_min of Eq. 2 for B0); 0 without edges.
double minimumEdgeLength(const TriMesh& mesh);

// The length of B0's boundary loop through vertex 0, after checking that it runs 0, 1, ..., n-1
// along boundary halfedges and is the only loop. Throws std::invalid_argument otherwise.
int checkedLoopLength(const TriMesh& base);

// Sec. 5.2, steps 1-4. Throws std::out_of_range for options outside the node's ranges,
// std::invalid_argument for a base that breaks the convention or whose l_min is 0, and
// BaseGrowthError when Eq. 2 would need more vertices than
// options.maxVertices.
BaseOptimizeResult optimizeBase(const TriMesh& base, const BaseOptimizeOptions& options);

}  // namespace geobrush
