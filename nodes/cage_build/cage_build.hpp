// Shell cage around a parameterized canvas (GeoBrush, Takayama et al. 2011,
// section 4.3): a coarse triangulation C of the parameter domain, doubled
// into top and bottom sheets joined along C's boundary, placed by extremal
// projections along the parameterization's normals and smoothed by Laplacian
// mesh optimization with those positions as soft constraints [NISA06].
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <optional>
#include <stdexcept>
#include <vector>

#include "geobrush/canvas.hpp"

namespace geobrush {

struct CageBuildOptions {
  // Cells of C across the larger side of the parameter domain's bounding box.
  int resolution = 8;
  // Extra thickness on both sides of the canvas, as a fraction of the larger
  // side of the parameter domain.
  double margin = 0.05;
  // Weight of the extremal positions against the Laplacian smoothness.
  double constraintWeight = 1.0;
  // How many cages may be built, each pushed out where the previous one left
  // canvas vertices outside, or smoother where it folded.
  int attempts = 12;
  std::function<bool()> cancelled;
};

struct CageBuildResult {
  Cage cage;
  double margin = 0;  // the base margin, in model units
  int attempts = 0;   // how many cages were built before one enclosed the canvas
};

// Thrown when no enclosing cage without self-intersections is found, or the
// input cannot be triangulated (empty or non-finite parameterization).
class CageBuildError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

CageBuildResult buildCage(const Parameterization& parameterization,
                          const CageBuildOptions& options = {});

// Generalized winding number of `point` with respect to a closed triangle
// mesh (sum of signed solid angles / 4 pi): 1 inside an outward mesh, 0 outside.
double windingNumber(const TriMesh& mesh, const Eigen::Vector3d& point);

// Which points a closed triangle mesh encloses, with the same answer as
// windingNumber(mesh, point) >= 0.5 but without visiting every face: an
// axis-parallel ray from the point crosses the mesh, and off the surface the
// winding number is the signed count of those crossings. The faces are binned
// in a grid over the plane perpendicular to the ray, so a point tests only the
// faces its ray can meet. Points within a tolerance (1e-9 of the mesh's size)
// of a face, or whose ray passes that close to an edge or vertex, get the
// winding number itself. The mesh must outlive the test.
class EnclosureTest {
 public:
  // Throws std::invalid_argument when the mesh has a boundary.
  explicit EnclosureTest(const TriMesh& closedMesh);
  explicit EnclosureTest(TriMesh&&) = delete;  // the mesh must outlive the test

  bool encloses(const Eigen::Vector3d& point) const;

  // The signed crossing count (the winding number off the surface), or
  // nothing where the ray or the point comes too close to the surface to
  // trust it.
  std::optional<int> crossingWindingNumber(const Eigen::Vector3d& point) const;

 private:
  struct Triangle {
    std::array<Eigen::Vector3d, 3> corners;
    Eigen::Vector3d normal;  // (b - a) x (c - a), unnormalized
    Eigen::AlignedBox3d box;
  };
  // How a triangle meets the ray: not at all, crossing it with the given sign,
  // or too closely to tell.
  enum class Crossing { None, Exits, Enters, Doubtful };

  Crossing crossing(const Triangle& triangle, const Eigen::Vector3d& point) const;
  int cellOf(double u, double v) const;
  void binTriangles();

  const TriMesh& mesh_;
  std::vector<Triangle> triangles_;
  Eigen::AlignedBox3d bounds_;  // the mesh's box grown by the tolerance
  double tolerance_ = 0;
  int axis_ = 2;  // the ray runs along +axis_; (u_, v_, axis_) is right-handed
  int u_ = 0;
  int v_ = 1;
  double cellSize_ = 1;
  int cellsU_ = 1;
  int cellsV_ = 1;
  std::vector<int> cellStart_;  // triangles of cell c: cellTriangles_[cellStart_[c], ...[c + 1])
  std::vector<int> cellTriangles_;
};

// Pairs of faces that intersect other than along a shared vertex or edge.
std::size_t countSelfIntersections(const TriMesh& mesh);

}  // namespace geobrush
