#include "transform.hpp"

#include <Eigen/LU>

#include <cmath>
#include <numbers>
#include <utility>

namespace geobrush {
namespace {

// Exact at whole quarter turns, so that turning an axis-aligned mesh keeps it axis-aligned.
std::pair<double, double> cosSinDegrees(double degrees) {
  const double reduced = std::remainder(degrees, 360.0);  // exact, in [-180, 180]
  if (reduced == 0) return {1.0, 0.0};
  if (reduced == 90) return {0.0, 1.0};
  if (reduced == -90) return {0.0, -1.0};
  if (std::abs(reduced) == 180) return {-1.0, 0.0};
  const double radians = reduced * std::numbers::pi / 180;
  return {std::cos(radians), std::sin(radians)};
}

void requireFinite(const Eigen::Vector3d& v, const char* option) {
  if (!v.allFinite()) throw TransformOptionError(option, "every entry must be a finite number");
}

}  // namespace

Eigen::Matrix3d eulerRotation(const Eigen::Vector3d& degrees) {
  const auto [cx, sx] = cosSinDegrees(degrees.x());
  const auto [cy, sy] = cosSinDegrees(degrees.y());
  const auto [cz, sz] = cosSinDegrees(degrees.z());
  Eigen::Matrix3d rx, ry, rz;
  rx << 1, 0, 0, 0, cx, -sx, 0, sx, cx;
  ry << cy, 0, sy, 0, 1, 0, -sy, 0, cy;
  rz << cz, -sz, 0, sz, cz, 0, 0, 0, 1;
  return rz * ry * rx;
}

AffineTransform affineTransform(const TransformOptions& options) {
  requireFinite(options.translate, "translate");
  requireFinite(options.rotateDegrees, "rotate");
  requireFinite(options.scale, "scale");
  requireFinite(options.pivot, "pivot");
  if ((options.scale.array() == 0).any()) {
    throw TransformOptionError("scale", "no entry may be 0 (the mesh would collapse)");
  }
  AffineTransform t;
  t.linear = eulerRotation(options.rotateDegrees) * options.scale.asDiagonal();
  t.offset = options.translate + options.pivot - t.linear * options.pivot;
  return t;
}

TriMesh transformMesh(const TriMesh& mesh, const TransformOptions& options) {
  const AffineTransform t = affineTransform(options);
  // Mirroring turns every face inside out; reversing the winding turns it back.
  const bool mirror = t.linear.determinant() < 0;

  TriMesh result;
  result.reserve(mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {
    const auto& p = mesh.point(TriMesh::VertexHandle(static_cast<int>(i)));
    const Eigen::Vector3d q = t.linear * Eigen::Vector3d(p[0], p[1], p[2]) + t.offset;
    result.add_vertex(toPoint(q));
  }
  std::vector<TriMesh::VertexHandle> corners;
  for (auto face : mesh.faces()) {
    corners.assign(mesh.cfv_begin(face), mesh.cfv_end(face));
    if (mirror) std::swap(corners[1], corners[2]);
    result.add_face(corners);
  }
  return result;
}

}  // namespace geobrush
