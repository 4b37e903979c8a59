// CGAL 5.5 as the reference for tests and benchmarks: its exact self-intersection test, distances
// to a surface, and its hole filling (Liepa's triangulate, refine and fair).
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "geobrush/mesh.hpp"

namespace geobrush::test {

// Intersecting face pairs by CGAL's Polygon_mesh_processing::self_intersections (exact
// predicates; faces sharing a vertex or an edge intersect only beyond what they share).
std::size_t cgalSelfIntersections(const TriMesh& mesh);

struct SurfaceDistance {
  double mean = 0.0;
  double max = 0.0;
};

// Distances from each point to the closest point of `surface` (CGAL's AABB tree).
SurfaceDistance cgalDistances(const std::vector<Eigen::Vector3d>& points, const TriMesh& surface);

struct CgalFill {
  TriMesh mesh;
  std::size_t newVertices = 0;
  std::size_t filledHoles = 0;
};

// triangulate_refine_and_fair_hole on every boundary loop with at most maxBorderEdges edges
// (0: all), the density control factor sqrt(2) and the given fairing continuity.
CgalFill cgalFillHoles(const TriMesh& mesh, unsigned continuity, std::size_t maxBorderEdges = 0);

}  // namespace geobrush::test
