// Automatic hole filling: each chosen boundary loop gets a chart of its own (the plane of the
// loop), a triangulation as dense as the mesh around the border, graded inward (Liepa, "Filling
// holes in meshes", SGP 2003, Sec. 3.2, done in the chart), and the membrane with G = 0 over it
// (GeoBrush paper, Eq. 3 with G = 0): the harmonic heights matching the border's values (C0), then
// for C1 the biharmonic positions matching the border's values and the slopes of the ring of faces
// outside it, weighed by the harmonic fill's shape. A fill that would cut the surface is refilled
// harmonic, then refused. Existing vertices never move; the new faces share the border's.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geobrush/mesh.hpp"

namespace geobrush {

// One boundary loop: its vertices in the order of their boundary halfedges, starting at the
// loop's smallest vertex index. Loops are numbered in the order of those smallest indices.
struct BoundaryLoop {
  std::vector<int> vertices;
  double length = 0.0;  // the sum of its edge lengths
};

std::vector<BoundaryLoop> boundaryLoops(const TriMesh& mesh);

enum class HoleSelection { All, AllButLargest, Listed };

struct FillHolesOptions {
  HoleSelection selection = HoleSelection::All;
  std::vector<int> loops;               // the loop ids filled with HoleSelection::Listed
  int maxBorderEdges = 0;               // loops with more border edges are left open; 0: no limit
  int continuity = 1;                   // 0: harmonic, 1: biharmonic (values and slopes)
  double density = 1.4142135623730951;  // Liepa's alpha: higher makes smaller triangles
};

struct HoleReport {
  int loop = 0;
  int borderEdges = 0;
  bool filled = false;
  std::string leftOpen;  // why a loop was not filled (not chosen, too long); empty when filled
  int continuity = 0;    // the one the fill has: 0 for a planar border or where slopes fold it
  std::string note;      // how the fill departs from the options, if it does
  int newVertices = 0;
  int newFaces = 0;
  double borderMeanEdge = 0.0;
  double newMeanEdge = 0.0;  // mean length of the edges the fill added (0 when none)
  double timeMs = 0.0;
};

struct FillHolesResult {
  TriMesh mesh;                   // the input's vertices and faces in their order, then the fills'
  std::vector<HoleReport> holes;  // one per boundary loop, by loop id
};

// A chosen loop that cannot be filled; the message names it.
class FillHolesError : public std::runtime_error {
 public:
  FillHolesError(int loop, const std::string& message) : std::runtime_error(message), loop_(loop) {}
  int loop() const { return loop_; }

 private:
  int loop_;
};

// Throws std::invalid_argument for bad options (a listed loop that does not exist) and
// FillHolesError for a chosen loop whose fill would cut the surface (or another fill).
FillHolesResult fillHoles(const TriMesh& mesh, const FillHolesOptions& options);

// Stages, exposed for tests.

// The chart of a loop: a plane through its centroid in which the loop is a simple polygon, run
// counter-clockwise, and the fill a height field over it; or, where no plane tried shows the loop
// as a simple polygon, a disc with the loop on its circle by arc length, and the fill's positions
// the membrane over it.
struct HoleChart {
  bool planar = true;
  Eigen::Vector3d origin, axisU, axisV, normal;
  std::vector<Eigen::Vector2d> border;  // the loop's vertices in the chart
  Eigen::Vector2d toChart(const Eigen::Vector3d& p) const;
  double height(const Eigen::Vector3d& p) const { return normal.dot(p - origin); }
  Eigen::Vector3d toSpace(const Eigen::Vector2d& uv, double h) const;
};

// The first plane (the loop's area normal, then its faces' mean normal) in which the loop is a
// simple polygon, else the disc.
HoleChart chartHole(const TriMesh& mesh, const BoundaryLoop& loop);

struct PlanarPatch {
  std::vector<Eigen::Vector2d> points;        // the border's first, in order, then the new ones
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise
};

// Triangulates the simple counter-clockwise polygon `border` and refines it until no triangle is
// larger than the sizes interpolated from `borderSize` (one per border point) allow.
// Throws std::runtime_error when the polygon has no ear (it is not simple).
PlanarPatch triangulatePolygon(const std::vector<Eigen::Vector2d>& border,
                               const std::vector<double>& borderSize, double density);

// Splits, at its midpoint, each chord of `patch` (over `loop`'s border points, in order) that
// joins two border points the mesh already joins by an edge: adding it again would make a
// non-manifold edge. `size` gets the new points' sizes.
void splitExistingChords(PlanarPatch& patch, const TriMesh& mesh, const BoundaryLoop& loop,
                         std::vector<double>& size);

// True when no two non-adjacent edges of the closed polygon touch and no point repeats.
bool isSimplePolygon(const std::vector<Eigen::Vector2d>& polygon);

}  // namespace geobrush
