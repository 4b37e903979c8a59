#include "detail_encode.hpp"

#include "geobrush/intersection.hpp"

#include <cmath>

#include "geobrush/domain_locator.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

void checkParameterization(const ParameterizationPtr& p, const std::string& port) {
  if (!p || !p->canvas || p->uv.size() != p->canvas->surface.n_vertices())
    throw DetailEncodeError(port, "the parameterization does not match its canvas");
  for (const auto& uv : p->uv)
    if (!uv.allFinite()) throw DetailEncodeError(port, "the parameterization has non-finite uv");
  if (p->canvas->surface.n_faces() == 0) throw DetailEncodeError(port, "the canvas has no faces");
}

// B's vertices 0..n-1 at F.boundary's positions (within 1e-9 of F's diagonal).
void checkConvention(const Canvas& feature, const TriMesh& base) {
  const std::size_t n = feature.boundary.size();
  if (n > base.n_vertices())
    throw DetailEncodeError("base", "B has " + std::to_string(base.n_vertices()) +
                                        " vertices, fewer than F's " + std::to_string(n) +
                                        " boundary vertices");
  const double tolerance = 1e-9 * boundingDiagonal(feature.surface);
  for (std::size_t i = 0; i < n; ++i) {
    const int v = feature.boundary[i];
    if (v < 0 || v >= int(feature.surface.n_vertices()))
      throw DetailEncodeError(
          "feature", "F's boundary lists vertex " + std::to_string(v) + ", not on its surface");
    const double gap = (pointOf(base, int(i)) - pointOf(feature.surface, v)).norm();
    if (!(gap <= tolerance))
      throw DetailEncodeError("base", "B's vertex " + std::to_string(i) +
                                          " is not at F's boundary vertex " + std::to_string(i) +
                                          " (" + std::to_string(gap) + " away)");
  }
}

// Per vertex i < n of B: its face of lowest index and its corner there.
std::vector<std::pair<int, int>> cornerFaces(const TriMesh& base, int n) {
  std::vector<std::pair<int, int>> corner(n, {-1, -1});
  for (auto f : base.faces()) {
    int k = 0;
    for (auto v : base.fv_range(f)) {
      if (v.idx() < n && corner[v.idx()].first < 0) corner[v.idx()] = {f.idx(), k};
      ++k;
    }
  }
  for (int i = 0; i < n; ++i)
    if (corner[i].first < 0)
      throw DetailEncodeError("base", "B's vertex " + std::to_string(i) + " has no face");
  return corner;
}

// The nearest barycentric coordinates of the triangle itself: negative ones raised to 0, the rest
// scaled to sum to 1 (the centroid where none is finite and positive).
Vector3d clampedToTriangle(const Vector3d& b) {
  if (!b.allFinite()) return Vector3d::Constant(1.0 / 3);
  const Vector3d positive = b.cwiseMax(0.0);
  const double sum = positive.sum();
  return sum > 0 ? Vector3d(positive / sum) : Vector3d::Constant(1.0 / 3);
}

}  // namespace

DetailEncoding encodeDetail(const ParameterizationPtr& feature, const ParameterizationPtr& base,
                            DetailMethod method) {
  checkParameterization(feature, "feature");
  checkParameterization(base, "base");
  const Canvas& f = *feature->canvas;
  const TriMesh& b = base->canvas->surface;
  checkConvention(f, b);
  const int n = int(f.boundary.size());
  const std::vector<std::pair<int, int>> corner = cornerFaces(b, n);
  std::vector<int> boundaryIndex(f.surface.n_vertices(), -1);
  for (int i = 0; i < n; ++i)
    boundaryIndex[f.boundary[i]] = i;
  const BaseFrameField field = baseFrameField(b, base->uv);
  const DomainLocator locator(*base);
  DetailEncoding encoding;
  encoding.feature = feature;
  encoding.base = base;
  encoding.method = method;
  const std::size_t count = f.surface.n_vertices();
  encoding.baseFace.resize(count);
  encoding.barycentric.resize(count);
  encoding.offset.resize(count);
  for (std::size_t v = 0; v < count; ++v) {
    if (const int i = boundaryIndex[v]; i >= 0) {
      encoding.baseFace[v] = corner[i].first;
      encoding.barycentric[v] = Vector3d::Unit(corner[i].second);
      encoding.offset[v] = Vector3d::Zero();
      continue;
    }
    // Outside every triangle the locator extrapolates from the nearest outline triangle, and on a
    // triangle the domain lays nearly flat its coordinates are huge: clamped onto the triangle,
    // the offset takes up the rest, so decoding over this base still returns the vertex and over
    // a moved base stays near it.
    const DomainHit hit = locator.locate(feature->uv[v]);
    const Vector3d onFace = clampedToTriangle(hit.barycentric);
    encoding.baseFace[v] = hit.face;
    encoding.barycentric[v] = onFace;
    encoding.offset[v] =
        encodeOffset(baseFace(b, field, hit.face), onFace, pointOf(f.surface, int(v)), method);
  }
  std::vector<int> faces(f.surface.n_faces());
  for (std::size_t k = 0; k < faces.size(); ++k)
    faces[k] = int(k);
  encoding.selfIntersections =
      selfIntersections(f.surface, faces, 1e-12 * boundingDiagonal(f.surface));
  return encoding;
}

std::vector<Vector3d> decodeOverOwnBase(const DetailEncoding& encoding) {
  const TriMesh& b = encoding.base->canvas->surface;
  const BaseFrameField field = baseFrameField(b, encoding.base->uv);
  std::vector<Vector3d> points(encoding.offset.size());
  for (std::size_t v = 0; v < points.size(); ++v) {
    points[v] = decodeOffset(baseFace(b, field, encoding.baseFace[v]), encoding.barycentric[v],
                             encoding.offset[v], encoding.method, 1.0);
  }
  return points;
}

}  // namespace geobrush
