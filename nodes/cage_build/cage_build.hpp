// Shell cage around a parameterized canvas (GeoBrush, Takayama et al. 2011,
// section 4.3): a coarse triangulation C of the parameter domain, doubled
// into top and bottom sheets joined along C's boundary, placed by extremal
// projections along the parameterization's normals and smoothed by Laplacian
// mesh optimization with those positions as soft constraints [NISA06].
#pragma once

#include <functional>
#include <stdexcept>

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

// Pairs of faces that intersect other than along a shared vertex or edge.
std::size_t countSelfIntersections(const TriMesh& mesh);

}  // namespace geobrush
