// Whether two triangles in space intersect: the separating-axis test over the axes that can part
// two triangles (their normals, the cross products of their edges, and for coplanar triangles
// the in-plane edge normals; Eberly, "Intersection of Convex Objects: The Method of Separating
// Axes", 2001).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "geobrush/mesh.hpp"

namespace geobrush {

using Triangle3 = std::array<Eigen::Vector3d, 3>;

// True when the closed triangles share a point or come closer than `tolerance` (a length, for
// rounding) along every axis; touching counts. Degenerate triangles never intersect.
bool trianglesIntersect(const Triangle3& a, const Triangle3& b, double tolerance);

// True when the triangles, seen along `direction` (projected on the plane across it), cover a
// common area of more than `share` of the smaller one's: triangles that only touch, at a shared
// corner or along a shared edge, do not overlap. Degenerate projections never overlap.
bool trianglesOverlapAlong(const Eigen::Vector3d& direction, const Triangle3& a, const Triangle3& b,
                           double share = 1e-6);

// The corners of face f.
Triangle3 faceTriangle(const TriMesh& mesh, int f);

// Face pairs of `mesh` that intersect, with at least one face in `faces`: faces with no corner in
// common that meet (within `tolerance`), faces sharing one vertex that meet beyond it, faces
// sharing an edge that fold flat onto each other (as CGAL's self_intersections counts them).
std::size_t selfIntersections(const TriMesh& mesh, const std::vector<int>& faces, double tolerance);

}  // namespace geobrush
