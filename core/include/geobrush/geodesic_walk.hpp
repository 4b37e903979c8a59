// Straightest geodesics on a triangle mesh (Polthier and Schmies, "Straightest geodesics on
// polyhedral surfaces", 1998): a walk from a point of a face in a tangent direction that unfolds
// each edge it crosses and leaves each vertex it meets so that the total angle around the vertex
// is split in half.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// Why a walk stopped.
enum class WalkStop {
  Completed,   // the whole length was walked
  Boundary,    // the walk reached a boundary edge or boundary vertex of the mesh
  Degenerate,  // the walk entered a face of zero area (or met a vertex next to one)
  FaceLimit,   // the walk entered as many faces as its budget allows (walkFaceBudget)
};

struct GeodesicWalkOptions {
  // The hard cap on the faces one walk may enter, whatever its length.
  int maxFaces = 1 << 22;
  // The mesh's mean edge length, read by walkFaceBudget; 0: measured from the mesh on each walk
  // (O(edges)), so that callers making many walks on one mesh pass it in.
  double meanEdge = 0;
  // A point whose barycentric coordinate at a corner is within this of 1 is at that corner: the
  // walk passes through the vertex. Small, so that snapping moves a point by at most this times an
  // edge; rounding alone puts an exact vertex hit within about 1e-15 of it.
  double vertexTolerance = 1e-12;
};

struct GeodesicWalkResult {
  WalkStop stop = WalkStop::Completed;
  int face = -1;                                          // the face the walk ended on
  Eigen::Vector3d point = Eigen::Vector3d::Zero();        // where it ended
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  // of `point` on `face`, fv order
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();    // arrival, unit, in face's plane
  double length = 0;                                      // the length walked
  int vertices = 0;                                       // vertices walked through
  // Every face entered, in order, the start face first (for a start at a vertex, the face it
  // leaves the vertex into); a face entered again is listed again.
  std::vector<int> faces;
  // points[i] is where the walk entered faces[i] (points[0] is the start), and the last is
  // `point`: the walk runs straight from points[i] to points[i + 1] inside faces[i].
  std::vector<Eigen::Vector3d> points;
};

// How many faces a walk of `length` may enter: a straight segment of length L crosses about
// 2 L / e faces of a regular triangulation with mean edge e; the budget allows eight times that,
// plus every face of the mesh once (a walk may sweep through fans of slivers), plus 16, and never
// more than options.maxFaces.
int walkFaceBudget(const TriMesh& mesh, double length, const GeodesicWalkOptions& options);

// Walks the straightest geodesic (Polthier-Schmies, Def. 4 and the discrete straightest
// geodesic of their Sec. 4) from `point` on `face` in `direction` (projected onto the face's plane)
// for `length`. A point at a vertex of the face starts from the vertex: a direction inside the
// face's corner keeps its angle to the corner's first edge, one outside it is spread over the rest
// of the vertex's total angle in proportion. Stops early at a boundary, at a degenerate face or
// when the face budget is spent, and says so in `stop`. Throws std::invalid_argument for a face
// out of range, a non-finite point or direction, a direction normal to the face, or a negative or
// non-finite length.
GeodesicWalkResult walkStraightest(const TriMesh& mesh, int face, const Eigen::Vector3d& point,
                                   const Eigen::Vector3d& direction, double length,
                                   const GeodesicWalkOptions& options = {});

// `direction` projected onto the plane of `face`, normalized, and turned by `angle` radians about
// the face's unit normal (counter-clockwise seen from the normal's tip): the turn at each corner
// of a walked polygon. Zero when the direction is normal to the face or the face is degenerate.
Eigen::Vector3d rotateInFace(const TriMesh& mesh, int face, const Eigen::Vector3d& direction,
                             double angle);

// The unit normal of a face from its corners in fv order; zero for a degenerate face.
Eigen::Vector3d faceUnitNormal(const TriMesh& mesh, int face);

}  // namespace geobrush
