// The base B0 of a feature region F: the optimal triangulation of F's boundary loop over the loop's
// own vertices (topology-free cut-and-paste, Sec. 5.1, Eq. 1), by the O(n^3) dynamic programme of
// Barequet and Sharir. B0 keeps cut_paste.hpp's convention: vertex i is F.boundary[i] at F's
// position and B0's boundary halfedges run from vertex i to vertex i + 1, as F's do.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// What each triangle costs; the programme minimizes the sum over the triangulation.
enum class TriangulationObjective {
  Area,       // Eq. 1: the triangle's area
  Perimeter,  // the triangle's perimeter: the sum is the loop's length plus twice the length of
              // the interior edges, so this is the triangulation of least total edge length
};

struct MinAreaOptions {
  TriangulationObjective objective = TriangulationObjective::Area;
  // Longer loops are refused: the programme keeps two n x n tables (12 n^2 bytes) and takes
  // n^3 / 6 steps (about 5 s for the area at 2000 vertices, on one core).
  int maxLoopVertices = 2000;
};

// A triangulation of the polygon 0..n-1: triangles (i, j, k) with i < k < j, and its cost.
struct LoopTriangulation {
  std::vector<std::array<int, 3>> triangles;  // in the order the programme splits the polygon
  double cost = 0.0;                          // W(0, n - 1): the objective summed
  // Triangles with corners on one line, used only where the loop leaves no other way.
  std::size_t degenerate = 0;
};

struct MinAreaResult {
  TriMesh base;                       // B0: the loop's vertices in order, n - 2 faces
  double objective = 0.0;             // the minimum the programme found
  double area = 0.0;                  // B0's total area
  double interiorEdgeLength = 0.0;    // the total length of B0's n - 3 interior edges
  std::size_t selfIntersections = 0;  // pairs of B0's faces that meet (intersection.hpp)
  std::size_t degenerate = 0;         // triangles with corners on one line
};

// One triangle's term of the objective.
double triangleCost(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    TriangulationObjective objective);

// The optimal triangulation of the closed polygon `loop` (Eq. 1, DP of Sec. 5.1):
// W(i, i + 1) = 0, W(i, j) = min over i < k < j of W(i, k) + W(k, j) + cost(v_i, v_k, v_j), ties
// to the smallest k; a degenerate triangle (corners on one line) costs more than any
// triangulation without one. Throws std::invalid_argument for fewer than 3 points.
LoopTriangulation optimalTriangulation(const std::vector<Eigen::Vector3d>& loop,
                                       TriangulationObjective objective);

// The mesh of a triangulation: vertex i at loop[i], each triangle (i, j, k) as that face, so its
// boundary halfedges run i -> i + 1.
TriMesh triangulationMesh(const std::vector<Eigen::Vector3d>& loop, const LoopTriangulation& t);

// B0 over the canvas's boundary loop, with its self-intersections counted. Throws
// std::invalid_argument for a loop of fewer than 3 or more than options.maxLoopVertices vertices,
// one that repeats a vertex, names one the surface lacks or does not run along the surface's
// boundary halfedges.
MinAreaResult minAreaTriangulate(const Canvas& canvas, const MinAreaOptions& options);

}  // namespace geobrush
