// The paper's interaction (section 3, Fig. 3-4) as edits of the graph: each brush dab, origin
// and canvas change becomes a param of the node that owns it, so a painted session is the graph
// file and replays headless. Each function returns an error for the user (naming the node and
// param) or an empty string; painting the same thing twice makes no second edit.
#pragma once

#include <Eigen/Core>
#include <string>

#include "clone_view.hpp"
#include "studio_document.hpp"

namespace geobrush::studio {

// The source canvas's origin (geobrush.canvas_grow "origin").
std::string setSourceOrigin(StudioDocument& document, const CloneRoles& roles,
                            const Eigen::Vector3d& point);
// A dab of the canvas brush (canvas_grow "dabs": x, y, z, radius); erasing removes the dabs
// whose centres lie within the brush.
std::string paintCanvas(StudioDocument& document, const CloneRoles& roles,
                        const Eigen::Vector3d& point, double radius, bool erase);
// The target canvas's origin (geobrush.dem "origin"): clicking it, or dragging the canvas
// across the target while the strokes, kept in the shared domain, stay.
std::string setTargetOrigin(StudioDocument& document, const CloneRoles& roles,
                            const Eigen::Vector3d& point);
// Turns the target canvas's axes (dem "angle", degrees) and scales it (dem "scale").
std::string turnTarget(StudioDocument& document, const CloneRoles& roles, double degrees);
std::string scaleTarget(StudioDocument& document, const CloneRoles& roles, double factor);
// A dab of the region brush in the shared domain (geobrush.strokes "dabs": u, v, radius, mode).
std::string paintRegion(StudioDocument& document, const CloneRoles& roles,
                        const Eigen::Vector2d& uv, double radius, bool subtract);

// A brush radius to start with: the last region dab's, else a twentieth of the source mesh's
// bounding-box diagonal.
double defaultBrushRadius(const StudioDocument& document, const CloneRoles& roles,
                          const CloneValues& values);

}  // namespace geobrush::studio
