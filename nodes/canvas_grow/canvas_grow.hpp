// Growing the source canvas P_s from a picked origin through painted dabs (paper sections 3.1
// and 4.2).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {

// One brush dab: a closed ball in space.
struct CanvasDab {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0;
};

struct CanvasGrowOptions {
  // The picked point; snapped to the nearest point of the surface.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  // The painted region is the union of the dabs' balls. A face is painted when each of its three
  // corners lies in some dab (not necessarily the same one).
  std::vector<CanvasDab> dabs;
  // How far the origin may lie from the surface, relative to the mesh's bounding-box diagonal.
  double originTolerance = 1e-2;
};

// An input that cannot give a canvas. `option()` names what to change: "origin", "dabs" (the
// painting) or "mesh" (the input surface).
class CanvasGrowError : public std::invalid_argument {
 public:
  CanvasGrowError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// Grows the canvas (section 4.2: flood fill from the origin, stopping at the painted region's
// border) over edge-adjacent painted faces of `source`. The canvas surface keeps the source's
// faces in increasing source face order, on the used source vertices in increasing source vertex
// order; `boundary` starts at its lowest surface vertex. `originVertex` is the corner of the
// origin face nearest to the origin point.
//
// Throws CanvasGrowError when the canvas would not be a region bounded by one loop (section 3.1):
// it covers a whole closed component, leaves holes (unpainted islands, ring-shaped painting, or a
// hole of the mesh inside), or touches itself at a vertex; and for bad input: no dabs, a
// non-finite or non-positive radius, a non-finite origin, an origin farther from the surface than
// `originTolerance`, an origin on a boundary of the mesh or outside every dab, a face under the
// origin that is not painted, zero-area faces in the region (rejected rather than skipped, since
// skipping one would punch a hole in the canvas), or a mesh with no faces or non-finite points.
Canvas growCanvas(const MeshPtr& source, const CanvasGrowOptions& options);

}  // namespace geobrush
