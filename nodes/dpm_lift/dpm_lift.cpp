#include "dpm_lift.hpp"

#include <algorithm>

#include "geobrush/exponential_map.hpp"
#include "geobrush/projective_map.hpp"

namespace geobrush {
namespace {

// The target's unit vertex normal at a canvas vertex, from the whole mesh it lies on.
Eigen::Vector3d vertexNormal(const Canvas& canvas, int v) {
  const bool onSource = canvas.source != nullptr;
  const TriMesh& mesh = onSource ? canvas.source->surface : canvas.surface;
  const int at = onSource ? canvas.sourceVertex[std::size_t(v)] : v;
  const Eigen::Vector3d n = angleWeightedNormal(mesh, TriMesh::VertexHandle(at));
  return n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : n;
}

// The vertex normals interpolated at a hit, weights clamped to the triangle (an extrapolated hit
// takes the normal of the nearest point of its triangle); the plane's normal where they cancel.
Eigen::Vector3d surfaceDirection(const Canvas& canvas, const DomainHit& hit,
                                 const Eigen::Vector3d& fallback) {
  const Eigen::Vector3d w = hit.barycentric.cwiseMax(0.0);
  const double sum = w.sum();
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto v : canvas.surface.fv_range(TriMesh::FaceHandle(hit.face))) {
    const double weight = sum > 0 ? w[k] / sum : 1.0 / 3;
    n += weight * vertexNormal(canvas, v.idx());
    ++k;
  }
  return n.norm() > 1e-12 ? Eigen::Vector3d(n.normalized()) : fallback;
}

}  // namespace

LiftResult liftVertices(const Parameterization& source, const Parameterization& target,
                        const DomainLocator& targetLocator, const std::vector<int>& vertices,
                        const LiftOptions& options) {
  const TriMesh& canvas = source.canvas->surface;
  const double lambda = target.scale;
  LiftResult result;
  result.points.reserve(vertices.size());
  for (int v : vertices) {
    const DomainHit hit = targetLocator.locate(source.uv[std::size_t(v)]);
    if (!hit.inside) result.extrapolated.push_back(v);
    const double h = offsetFromPlane(source.origin, pointOf(canvas, v));
    const Eigen::Vector3d d = options.direction == OffsetDirection::Plane
                                  ? target.origin.normal
                                  : surfaceDirection(*target.canvas, hit, target.origin.normal);
    result.points.push_back(hit.point + lambda * h * d);
  }
  std::sort(result.extrapolated.begin(), result.extrapolated.end());
  return result;
}

}  // namespace geobrush
