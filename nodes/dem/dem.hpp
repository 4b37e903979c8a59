// The target canvas P_t and its map E_t, grown together (GeoBrush paper section 4.2, last
// paragraph; section 3.1): the original DEM of Schmidt, Grimm, Wyvill 2006 on the target surface,
// expressed in the domain shared with the source map E_s.
#pragma once

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {

struct TargetDemOptions {
  // The picked target origin; snapped to the nearest point of the surface.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  // Turns the target's (u, v) axes about the origin normal, as DemOptions::angleDegrees does for
  // the source: with the same angle on both canvases, their global +y directions correspond.
  double angleDegrees = 0;
  // lambda: a target distance is lambda times the domain distance (section 3: the user's scale).
  double scale = 1;
  // Extra coverage beyond the disk around the domain origin that holds E_s(P_s), as a fraction of
  // its radius (the source cage reaches about two grid cells beyond the canvas).
  double margin = 0.25;
  // A larger domain disk to cover where the target allows it, e.g. the one holding the source
  // cage's columns (the cage's grid spans the bounding square of the canvas' disk): when covering
  // it would wrap the canvas around the target or take in one of its holes, the canvas covers the
  // disk of the margin alone. 0: none.
  double preferredRadius = 0;
  // How far the origin may lie from the surface, relative to the mesh's bounding-box diagonal.
  double originTolerance = 1e-2;
  // Keep holes of the target mesh (boundary loops it encloses) inside the canvas instead of
  // refusing them: what hole filling needs. The canvas then has one boundary loop per hole
  // besides its outer one.
  bool keepHoles = false;
};

// An input that gives no target canvas. `option()` names what to change: "origin", "angle",
// "scale", "margin", "mesh" (the target surface) or "source" (the source map).
class TargetDemError : public std::invalid_argument {
 public:
  TargetDemError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// The target surface with what every target DEM on it reads: computed once and kept while the
// canvas is dragged across it (its vertex normals and nearest-point search would otherwise cost
// as much as the DEM itself on a large target).
class PreparedTarget {
 public:
  // Throws TargetDemError("mesh") for a missing mesh, one without faces or with a non-finite
  // coordinate.
  explicit PreparedTarget(MeshPtr mesh);

  const MeshPtr& mesh() const { return mesh_; }
  double diagonal() const { return diagonal_; }
  // Angle-weighted unit normal; zero where the vertex's faces are degenerate.
  const Eigen::Vector3d& normal(int vertex) const { return normals_[std::size_t(vertex)]; }
  SurfacePoint nearest(const Eigen::Vector3d& point) const { return locator_.nearest(point); }

 private:
  MeshPtr mesh_;
  double diagonal_ = 0;
  std::vector<Eigen::Vector3d> normals_;
  SurfaceLocator locator_;
};

struct TargetDemResult {
  Canvas canvas;                        // P_t on the target mesh
  std::vector<Eigen::Vector2d> uv;      // per canvas vertex, in the shared domain: E_t / lambda
  std::vector<Eigen::Vector3d> normal;  // per canvas vertex: the target's surface normals
  Frame origin;                         // at the snapped origin, uv (0, 0)
  // (1 + margin) * the largest |uv| of the source, in the domain, or the preferred radius when
  // the canvas covers it.
  double requiredRadius = 0;
};

// Grows P_t and E_t together: target vertices are fixed one by one in order of Dijkstra distance
// from the origin (the core ExponentialMapGrowth with surface normals and rescaled steps).
//
// Stopping rule: with R = requiredRadius, a fixed vertex v is "needed" when
// lambda |uv(v)| < lambda R + l(v) / 2, l(v) being its longest mesh edge; growth stops once every
// needed vertex has all its mesh neighbours fixed. Then every needed vertex is interior to the
// region of faces with three fixed corners, and every boundary edge of that region has both ends
// at least half an edge beyond R, so (up to the DEM's edge-length distortion) the disk of radius R
// lies inside the region's uv image. Holes and pinched vertices of the region in the outer band
// are closed by requiring the neighbours of their vertices too and growing on.
//
// Throws TargetDemError for: a non-finite or non-positive scale, a negative margin, an empty or
// non-finite source map, an origin off the surface or on a boundary of the target, a needed
// vertex on a boundary of the target (the domain runs off the target), and a region that would
// take more than half of the target's vertices or exhaust its component (on a closed surface it
// would wrap around: use a smaller scale or source canvas).
TargetDemResult targetExponentialMap(const PreparedTarget& target,
                                     const std::vector<Eigen::Vector2d>& sourceUv,
                                     const TargetDemOptions& options);

// The same for a target used once.
TargetDemResult targetExponentialMap(const MeshPtr& target,
                                     const std::vector<Eigen::Vector2d>& sourceUv,
                                     const TargetDemOptions& options);

}  // namespace geobrush
