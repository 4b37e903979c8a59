#include "clone_edits.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace geobrush::studio {
namespace {

std::string noNode(const std::string& role) {
  return "the graph has no " + role + " node to edit";
}

template <typename T>
T paramOr(const StudioDocument& document, const std::string& node, const std::string& name,
          T fallback) {
  const auto value = document.param(node, name);
  if (!value || !std::holds_alternative<T>(*value)) return fallback;
  return std::get<T>(*value);
}

}  // namespace

std::string setSourceOrigin(StudioDocument& document, const CloneRoles& roles,
                            const Eigen::Vector3d& point) {
  if (roles.sourceCanvas.empty()) return noNode("source canvas (geobrush.canvas_grow)");
  return document.setParam(roles.sourceCanvas, "origin", Vec3{point.x(), point.y(), point.z()});
}

std::string paintCanvas(StudioDocument& document, const CloneRoles& roles,
                        const Eigen::Vector3d& point, double radius, bool erase) {
  if (roles.sourceCanvas.empty()) return noNode("source canvas (geobrush.canvas_grow)");
  auto dabs = paramOr(document, roles.sourceCanvas, "dabs", std::vector<double>{});
  if (erase) {
    std::vector<double> kept;
    for (std::size_t i = 0; i + 4 <= dabs.size(); i += 4)
      if ((Eigen::Vector3d(dabs[i], dabs[i + 1], dabs[i + 2]) - point).norm() > radius)
        kept.insert(kept.end(), dabs.begin() + i, dabs.begin() + i + 4);
    dabs = std::move(kept);
  } else {
    dabs.insert(dabs.end(), {point.x(), point.y(), point.z(), radius});
  }
  return document.setParam(roles.sourceCanvas, "dabs", dabs);
}

std::string setTargetOrigin(StudioDocument& document, const CloneRoles& roles,
                            const Eigen::Vector3d& point) {
  if (roles.targetMap.empty()) return noNode("target canvas (geobrush.dem)");
  return document.setParam(roles.targetMap, "origin", Vec3{point.x(), point.y(), point.z()});
}

std::string turnTarget(StudioDocument& document, const CloneRoles& roles, double degrees) {
  if (roles.targetMap.empty()) return noNode("target canvas (geobrush.dem)");
  // Kept in (-180, 180], so that turning round and round does not grow the number.
  double angle = paramOr(document, roles.targetMap, "angle", 0.0) + degrees;
  angle = std::remainder(angle, 360.0);
  if (angle == -180.0) angle = 180.0;
  return document.setParam(roles.targetMap, "angle", angle);
}

std::string scaleTarget(StudioDocument& document, const CloneRoles& roles, double factor) {
  if (roles.targetMap.empty()) return noNode("target canvas (geobrush.dem)");
  if (!(factor > 0)) return "the scale factor must be positive";
  return document.setParam(roles.targetMap, "scale",
                           paramOr(document, roles.targetMap, "scale", 1.0) * factor);
}

std::string paintRegion(StudioDocument& document, const CloneRoles& roles,
                        const Eigen::Vector2d& uv, double radius, bool subtract) {
  if (roles.strokes.empty()) return noNode("strokes (geobrush.strokes)");
  auto dabs = paramOr(document, roles.strokes, "dabs", std::vector<double>{});
  dabs.insert(dabs.end(), {uv.x(), uv.y(), radius, subtract ? -1.0 : 1.0});
  return document.setParam(roles.strokes, "dabs", dabs);
}

double defaultBrushRadius(const StudioDocument& document, const CloneRoles& roles,
                          const CloneValues& values) {
  const auto dabs = paramOr(document, roles.strokes, "dabs", std::vector<double>{});
  if (dabs.size() >= 4 && dabs[dabs.size() - 2] > 0) return dabs[dabs.size() - 2];
  if (!values.sourceMesh) return 1;
  return std::max(boundsOf(values.sourceMesh->surface).diagonal().norm() / 20, 1e-4);
}

}  // namespace geobrush::studio
