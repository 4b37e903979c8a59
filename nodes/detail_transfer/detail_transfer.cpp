#include "detail_transfer.hpp"

#include <algorithm>
#include <map>
#include <string>

#include "geobrush/domain_locator.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {
namespace {

// The walked points' places in the target feature's domain: each lies on a face of the region
// (the walk's own face where the region holds it, else the region's nearest point, e.g. for a
// point on the region's outline given with a face outside); its barycentric coordinates there
// carry the face's uv.
std::vector<Eigen::Vector2d> walkedDomainPoints(const Parameterization& targetFeature,
                                                const SurfacePath& walk) {
  const Canvas& region = *targetFeature.canvas;
  std::map<int, int> canvasFace;
  for (std::size_t f = 0; f < region.sourceFace.size(); ++f)
    canvasFace.emplace(region.sourceFace[f], int(f));
  const SurfaceLocator nearest(region.surface);
  std::vector<Eigen::Vector2d> uv(walk.point.size());
  for (std::size_t k = 0; k < walk.point.size(); ++k) {
    const auto at = canvasFace.find(walk.face[k]);
    const int face = at != canvasFace.end() ? at->second : nearest.nearest(walk.point[k]).face;
    std::array<int, 3> corners{};
    int c = 0;
    for (auto v : region.surface.fv_range(TriMesh::FaceHandle(face)))
      corners[std::size_t(c++)] = v.idx();
    const Eigen::Vector3d a = pointOf(region.surface, corners[0]);
    Eigen::Matrix<double, 3, 2> edges;
    edges << pointOf(region.surface, corners[1]) - a, pointOf(region.surface, corners[2]) - a;
    const Eigen::Vector2d st = edges.colPivHouseholderQr().solve(walk.point[k] - a);
    uv[k] = (1 - st.x() - st.y()) * targetFeature.uv[std::size_t(corners[0])] +
            st.x() * targetFeature.uv[std::size_t(corners[1])] +
            st.y() * targetFeature.uv[std::size_t(corners[2])];
  }
  return uv;
}

std::vector<Eigen::Vector2d> outline(const Parameterization& base) {
  std::vector<Eigen::Vector2d> polygon;
  for (int v : base.canvas->boundary)
    polygon.push_back(base.uv[std::size_t(v)]);
  return polygon;
}

Eigen::Vector2d apply(const Eigen::Matrix3d& similarity, const Eigen::Vector2d& uv) {
  return (similarity * uv.homogeneous()).hnormalized();
}

struct Alignment {
  Eigen::Matrix3d similarity;
  double shrink = 1;
  double residual = 0;
  std::size_t uncovered = 0;
};

// Umeyama from the source base's loop to the walked loop, then shrunk about the walked loop's
// centre until every source base vertex lands inside the target base's outline.
Alignment alignBases(const Parameterization& sourceBase, const std::vector<Eigen::Vector2d>& walked,
                     const Parameterization& targetBase, const DetailTransferOptions& options) {
  const auto& loop = sourceBase.canvas->boundary;
  std::vector<Eigen::Vector2d> from;
  for (int v : loop)
    from.push_back(sourceBase.uv[std::size_t(v)]);
  Alignment a;
  a.similarity = fitSimilarity2d(from, walked);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < from.size(); ++k) {
    a.residual += (apply(a.similarity, from[k]) - walked[k]).squaredNorm() / double(from.size());
    centre += walked[k] / double(walked.size());
  }
  a.residual = std::sqrt(a.residual);
  const std::vector<Eigen::Vector2d> target = outline(targetBase);
  Eigen::AlignedBox2d box;
  for (const auto& p : target)
    box.extend(p);
  const double tolerance = 1e-9 * box.diagonal().norm();
  auto uncovered = [&](double s) {
    std::size_t count = 0;
    for (const auto& uv : sourceBase.uv)
      count += !insidePolygon(target, centre + s * (apply(a.similarity, uv) - centre), tolerance);
    return count;
  };
  a.uncovered = uncovered(1);
  for (int k = 0; k < options.maxShrinks && a.uncovered > 0; ++k) {
    a.shrink *= options.shrinkStep;
    a.uncovered = uncovered(a.shrink);
  }
  Eigen::Matrix3d shrink = Eigen::Matrix3d::Identity();
  shrink.topLeftCorner<2, 2>() *= a.shrink;
  shrink.topRightCorner<2, 1>() = (1 - a.shrink) * centre;
  a.similarity = shrink * a.similarity;
  return a;
}

std::size_t allFaceIntersections(const TriMesh& mesh) {
  std::vector<int> faces(mesh.n_faces());
  for (std::size_t f = 0; f < faces.size(); ++f)
    faces[f] = int(f);
  return selfIntersections(mesh, faces, 1e-12 * boundingDiagonal(mesh));
}

std::size_t newFeatureIntersections(std::size_t before, const TriMesh& pasted) {
  const std::size_t after = allFaceIntersections(pasted);
  return after > before ? after - before : 0;
}

void checkInputs(const DetailEncoding& encoding, const Parameterization& targetFeature,
                 const Parameterization& targetBase, const SurfacePath& walk) {
  if (!encoding.feature || !encoding.base) throw std::invalid_argument("the encoding is empty");
  if (encoding.baseFace.size() != encoding.feature->canvas->surface.n_vertices())
    throw std::invalid_argument("the encoding does not match its feature");
  const std::size_t loop = encoding.base->canvas->boundary.size();
  if (walk.point.size() != loop || walk.face.size() != loop)
    throw std::invalid_argument("the walk has " + std::to_string(walk.point.size()) +
                                " points, the source base's loop " + std::to_string(loop));
  if (targetFeature.uv.size() != targetFeature.canvas->surface.n_vertices() ||
      targetBase.uv.size() != targetBase.canvas->surface.n_vertices())
    throw std::invalid_argument("a target parameterization does not match its canvas");
}

}  // namespace

DetailTransferResult transferDetail(const DetailEncoding& encoding,
                                    const Parameterization& targetFeature,
                                    const Parameterization& targetBase, const SurfacePath& walk,
                                    const DetailTransferOptions& options) {
  checkInputs(encoding, targetFeature, targetBase, walk);
  const Parameterization& sourceBase = *encoding.base;
  const Alignment alignment =
      alignBases(sourceBase, walkedDomainPoints(targetFeature, walk), targetBase, options);

  // Step 1: the source base laid onto the target base.
  TriMesh movedBase = sourceBase.canvas->surface;
  const DomainLocator locator(targetBase);
  for (auto v : movedBase.vertices()) {
    const DomainHit hit =
        locator.locate(apply(alignment.similarity, sourceBase.uv[std::size_t(v.idx())]));
    movedBase.set_point(v, TriMesh::Point(hit.point.x(), hit.point.y(), hit.point.z()));
  }
  const BaseFrameField field = baseFrameField(movedBase, sourceBase.uv);

  // Step 2: the feature rebuilt over the moved faces.
  DetailTransferResult result;
  result.pasted = encoding.feature->canvas->surface;
  for (auto v : result.pasted.vertices()) {
    const std::size_t i = std::size_t(v.idx());
    const Eigen::Vector3d x =
        decodeOffset(baseFace(movedBase, field, encoding.baseFace[i]), encoding.barycentric[i],
                     encoding.offset[i], encoding.method, walk.scale);
    result.pasted.set_point(v, toPoint(x));
  }
  for (const auto& uv : encoding.feature->uv)
    result.placedUv.push_back(apply(alignment.similarity, uv));
  result.newSelfIntersections = newFeatureIntersections(encoding.selfIntersections, result.pasted);
  result.alignment = alignment.similarity;
  result.shrink = alignment.shrink;
  result.alignmentResidual = alignment.residual;
  result.uncovered = alignment.uncovered;
  return result;
}

}  // namespace geobrush
