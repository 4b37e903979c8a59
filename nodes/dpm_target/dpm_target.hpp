// The target stamp of GPU texture cloning (gpu-texture-cloning.txt section 2, last paragraph: "the
// user makes a stamped mesh on the target mesh as the corresponding source stamped mesh"; the
// stamp itself is specs/alternatives-001-004.md 1.2 "Target stamp"): the direct projective map
// around the target origin, in the domain shared with the source map.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {

struct ProjectiveStampOptions {
  // The picked target origin o_T; snapped to the nearest point of the surface.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  // The view n_PT (any length); zero: the target's surface normal at the snapped origin.
  Eigen::Vector3d view = Eigen::Vector3d::Zero();
  // Turns the target's (u, v) axes about n_PT, as the source's angle does.
  double angleDegrees = 0;
  // lambda: a target distance is lambda times the domain distance.
  double scale = 1;
  // Coverage beyond the disc holding the source map, as a fraction of its radius.
  double margin = 0.25;
  // How far the origin may lie from the surface, relative to the mesh's bounding-box diagonal
  // (geobrush.dem's rule).
  double originTolerance = 1e-2;
  // Keep holes of the target mesh inside the canvas, and let the canvas run onto the mesh's
  // boundary, instead of refusing both.
  bool keepHoles = false;
};

// An input that gives no stamp. `option()` names what to change: "origin", "view", "angle",
// "scale", "margin", "mesh" (the target surface) or "source" (the source map).
class ProjectiveStampError : public std::invalid_argument {
 public:
  ProjectiveStampError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// The target mesh with its nearest-point search, built once per target and kept while the stamp
// is dragged across it.
class StampTarget {
 public:
  // Throws ProjectiveStampError("mesh") for a missing mesh, one without faces or with a
  // non-finite coordinate.
  explicit StampTarget(MeshPtr mesh);

  const MeshPtr& mesh() const { return mesh_; }
  double diagonal() const { return diagonal_; }
  SurfacePoint nearest(const Eigen::Vector3d& point) const { return locator_.nearest(point); }

 private:
  MeshPtr mesh_;
  double diagonal_ = 0;
  SurfaceLocator locator_;
};

struct ProjectiveStampResult {
  Canvas canvas;                            // the target canvas, on the target mesh
  std::vector<Eigen::Vector2d> uv;          // per canvas vertex: R_angle (x - o_T) / lambda
  Frame origin;                             // plane P_T at the snapped origin: normal n_PT
  std::vector<std::uint8_t> reversedFaces;  // per canvas face: n_f . n_PT <= 0 (not grown)
  double radius = 0;                        // (1 + margin) R_s: the domain disc covered
};

// The stamp: uv_T = ((x - o_T) . e_u, (x - o_T) . e_v) / lambda with originFrame's axes turned by
// the angle; the canvas is the faces edge-connected to the origin face through faces whose uv
// triangle meets the disc of radius (1 + margin) R_s (R_s the largest |uv| of the source map), so
// that where the target does not fold under the view the canvas' uv image holds that disc.
// Pinched vertices are cut off. Throws ProjectiveStampError for bad options or source, an origin
// off the surface, a canvas that takes in a whole closed component ("scale"), runs onto the
// mesh's boundary ("scale", unless keepHoles) or has more than one boundary loop ("mesh": a hole
// of the target, or a fold, inside the disc; holes of the mesh are kept with keepHoles).
ProjectiveStampResult projectiveStamp(const StampTarget& target,
                                      const std::vector<Eigen::Vector2d>& sourceUv,
                                      const ProjectiveStampOptions& options);

}  // namespace geobrush
