#include "detail_transfer.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <map>

#include "base_fixtures.hpp"
#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/surface_point.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Uv = std::function<Eigen::Vector2d(const Eigen::Vector3d&)>;

// A base by the pipeline's convention: the feature's loop, then its centroid, fanned.
MeshPtr fanBase(const Canvas& feature) {
  TriMesh base;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : feature.boundary) {
    base.add_vertex(feature.surface.point(TriMesh::VertexHandle(v)));
    centroid += pointOf(feature.surface, v) / double(feature.boundary.size());
  }
  const auto c = base.add_vertex(toPoint(centroid));
  const int n = int(feature.boundary.size());
  for (int i = 0; i < n; ++i)
    base.add_face(TriMesh::VertexHandle((i + 1) % n), TriMesh::VertexHandle(i), c);
  return std::make_shared<const Mesh>(base);
}

ParameterizationPtr parameterize(const CanvasPtr& canvas, const Uv& uv) {
  auto p = std::make_shared<Parameterization>();
  p->canvas = canvas;
  for (auto v : canvas->surface.vertices()) {
    p->uv.push_back(uv(pointOf(canvas->surface, v.idx())));
    p->normal.push_back(Eigen::Vector3d::UnitZ());
  }
  return p;
}

// The encoding detail_encode makes: each feature vertex located on the base in the domain.
DetailEncoding encode(const ParameterizationPtr& feature, const ParameterizationPtr& base,
                      DetailMethod method = DetailMethod::SmoothFrame) {
  DetailEncoding encoding;
  encoding.method = method;
  encoding.feature = feature;
  encoding.base = base;
  const DomainLocator locator(*base);
  const TriMesh& b = base->canvas->surface;
  const BaseFrameField field = baseFrameField(b, base->uv);
  for (auto v : feature->canvas->surface.vertices()) {
    const DomainHit hit = locator.locate(feature->uv[std::size_t(v.idx())]);
    encoding.baseFace.push_back(hit.face);
    encoding.barycentric.push_back(hit.barycentric);
    encoding.offset.push_back(encodeOffset(baseFace(b, field, hit.face), hit.barycentric,
                                           pointOf(feature->canvas->surface, v.idx()), method));
  }
  return encoding;
}

// A walk that lands each base loop vertex's domain point where `place` puts it on `target`.
SurfacePath walkTo(const MeshPtr& target, const Parameterization& base,
                   const std::function<Eigen::Vector3d(const Eigen::Vector2d&)>& place,
                   double scale) {
  SurfacePath walk;
  walk.mesh = target;
  walk.scale = scale;
  for (int v : base.canvas->boundary) {
    const SurfacePoint at = nearestSurfacePoint(target->surface, place(base.uv[std::size_t(v)]));
    walk.face.push_back(at.face);
    walk.point.push_back(at.point);
  }
  return walk;
}

double bump(double x, double y) {
  const double s = 1 - (x * x + y * y) / 0.16;
  return s > 0 ? 0.3 * s * s : 0.0;
}

struct Source {
  MeshPtr mesh;
  CanvasPtr feature;
  ParameterizationPtr featureUv, baseUv;
};

Source bumpSource() {
  Source s;
  s.mesh = test::heightGrid(30, bump);
  const int centre = nearestSurfacePoint(s.mesh->surface, {0.01, 0.02, 0.3}).face;
  s.feature = std::make_shared<const Canvas>(test::growDiscCanvas(s.mesh, centre, 0.6));
  const Uv xy = [](const Eigen::Vector3d& p) { return Eigen::Vector2d(p.x(), p.y()); };
  s.featureUv = parameterize(s.feature, xy);
  s.baseUv = parameterize(std::make_shared<const Canvas>(canvasOfMesh(fanBase(*s.feature))), xy);
  return s;
}

TEST(DetailTransfer, OntoItsOwnBaseTheFeatureComesBackUnchanged) {
  const Source s = bumpSource();
  const DetailEncoding encoding = encode(s.featureUv, s.baseUv);
  const SurfacePath walk = walkTo(
      s.mesh, *s.baseUv,
      [&](const Eigen::Vector2d& u) { return DomainLocator(*s.featureUv).locate(u).point; }, 1.0);
  const DetailTransferResult result = transferDetail(encoding, *s.featureUv, *s.baseUv, walk);
  EXPECT_EQ(result.shrink, 1.0);
  EXPECT_EQ(result.uncovered, 0u);
  const double diagonal = boundingDiagonal(s.feature->surface);
  for (auto v : result.pasted.vertices())
    EXPECT_LT((pointOf(result.pasted, v.idx()) - pointOf(s.feature->surface, v.idx())).norm(),
              1e-9 * diagonal);
}

TEST(DetailTransfer, OntoAMovedPlaneTheFeatureIsASimilarCopy) {
  const Source s = bumpSource();
  const DetailEncoding encoding = encode(s.featureUv, s.baseUv);
  const double lambda = 0.7;
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  rigid.pretranslate(Eigen::Vector3d(4, -1, 2));
  const MeshPtr target = test::heightGrid(
      40, [](double, double) { return 0.0; }, rigid);
  const auto place = [&](const Eigen::Vector2d& u) {
    return Eigen::Vector3d(rigid * Eigen::Vector3d(lambda * u.x(), lambda * u.y(), 0));
  };
  const int centre = nearestSurfacePoint(target->surface, place({0.01, 0.02})).face;
  const auto region = std::make_shared<const Canvas>(test::growDiscCanvas(target, centre, 0.8));
  const Uv targetUv = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector2d((rigid.inverse() * p).head<2>() / lambda);
  };
  const auto targetFeature = parameterize(region, targetUv);
  const auto targetBase =
      parameterize(std::make_shared<const Canvas>(canvasOfMesh(fanBase(*region))), targetUv);
  const DetailTransferResult result = transferDetail(encoding, *targetFeature, *targetBase,
                                                     walkTo(target, *s.baseUv, place, lambda));
  EXPECT_EQ(result.shrink, 1.0);
  EXPECT_LT(result.alignmentResidual, 1e-12);
  for (auto v : result.pasted.vertices()) {
    const Eigen::Vector3d expected = rigid * (lambda * pointOf(s.feature->surface, v.idx()));
    EXPECT_LT((pointOf(result.pasted, v.idx()) - expected).norm(), 1e-9);
  }
}

// A canvas as a base by the pipeline's convention: its loop's vertices first, in order, then the
// others, with the same faces.
MeshPtr canvasAsBase(const Canvas& canvas) {
  std::vector<int> order(canvas.surface.n_vertices(), -1);
  TriMesh base;
  auto add = [&](int v) {
    order[std::size_t(v)] = base.add_vertex(canvas.surface.point(TriMesh::VertexHandle(v))).idx();
  };
  for (int v : canvas.boundary)
    add(v);
  for (auto v : canvas.surface.vertices())
    if (order[std::size_t(v.idx())] < 0) add(v.idx());
  for (auto f : canvas.surface.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto v : canvas.surface.fv_range(f))
      corners.emplace_back(order[std::size_t(v.idx())]);
    base.add_face(corners);
  }
  return std::make_shared<const Mesh>(base);
}

// The bump pasted onto a plane and into a valley whose sides meet at 60 degrees (a convex feature
// in a concave region, the paper's admitted failure): over the valley the offsets along the sides'
// normals cross above its floor, and the transfer says so; over the plane nothing crosses.
TEST(DetailTransfer, AConvexFeatureInAConcaveValleyCutsIntoItselfAndSaysSo) {
  const Source s = bumpSource();
  const DetailEncoding encoding = encode(s.featureUv, s.baseUv);
  for (const double slope : {0.0, std::tan(60.0 * M_PI / 180)}) {
    const MeshPtr target =
        test::heightGrid(40, [&](double x, double) { return slope * std::abs(x); });
    const int centre = nearestSurfacePoint(target->surface, {0.01, 0.02, 0}).face;
    const auto region = std::make_shared<const Canvas>(test::growDiscCanvas(target, centre, 0.8));
    const Uv xy = [](const Eigen::Vector3d& p) { return Eigen::Vector2d(p.x(), p.y()); };
    const auto targetFeature = parameterize(region, xy);
    const auto targetBase =
        parameterize(std::make_shared<const Canvas>(canvasOfMesh(canvasAsBase(*region))), xy);
    const auto place = [&](const Eigen::Vector2d& u) {
      return Eigen::Vector3d(u.x(), u.y(), slope * std::abs(u.x()));
    };
    const DetailTransferResult result = transferDetail(encoding, *targetFeature, *targetBase,
                                                       walkTo(target, *s.baseUv, place, 1.0));
    if (slope == 0)
      EXPECT_EQ(result.newSelfIntersections, 0u);
    else
      EXPECT_GT(result.newSelfIntersections, 0u);
  }
}

// Runs a node type on `inputs` and returns its output `port`.
template <typename T>
std::shared_ptr<const T> nodeOutput(const std::string& type,
                                    std::map<std::string, ValuePtr, std::less<>> inputs,
                                    const std::string& port) {
  const NodeType* node = test::registry().find(type);
  EXPECT_NE(node, nullptr) << type;
  test::DirectContext ctx(*node, std::move(inputs));
  test::run(node->create(), ctx);
  return std::dynamic_pointer_cast<const T>(ctx.outputs.at(port));
}

// A genus-1 feature of a real mesh (torus.obj without one vertex's faces), encoded and
// parameterized by the pipeline's own nodes, transferred onto its own base: it comes back.
TEST(DetailTransfer, AGenusOneFeatureOfTheTorusComesBackOverItsOwnBase) {
  const MeshPtr torus = readMesh(test::meshPath("torus.obj")).mesh;
  std::vector<char> removed(torus->surface.n_faces(), 0);
  for (auto f : torus->surface.vf_range(TriMesh::VertexHandle(0)))
    removed[std::size_t(f.idx())] = 1;
  std::vector<int> kept;
  for (std::size_t f = 0; f < removed.size(); ++f)
    if (!removed[f]) kept.push_back(int(f));
  const CanvasPtr feature = test::canvasOf(torus, kept);
  ASSERT_EQ(test::topology(feature->surface).eulerCharacteristic, -1);  // genus 1, one loop
  const MeshPtr base = test::centroidFan(*feature);
  const auto featureUv = nodeOutput<Parameterization>(
      "geobrush.intrinsic_param", {{"feature", feature}, {"base", base}}, "feature");
  const auto baseUv = nodeOutput<Parameterization>("geobrush.intrinsic_param",
                                                   {{"feature", feature}, {"base", base}}, "base");
  const auto encoding = nodeOutput<DetailEncoding>(
      "geobrush.detail_encode", {{"feature", featureUv}, {"base", baseUv}}, "encoding");
  const SurfacePath walk = walkTo(
      torus, *baseUv,
      [&](const Eigen::Vector2d& u) { return DomainLocator(*featureUv).locate(u).point; }, 1.0);
  const DetailTransferResult result = transferDetail(*encoding, *featureUv, *baseUv, walk);
  EXPECT_EQ(result.shrink, 1.0);
  const double diagonal = boundingDiagonal(feature->surface);
  double worst = 0;
  for (auto v : result.pasted.vertices())
    worst = std::max(worst,
                     (pointOf(result.pasted, v.idx()) - pointOf(feature->surface, v.idx())).norm());
  EXPECT_LT(worst, 1e-9 * diagonal);
  EXPECT_EQ(result.newSelfIntersections, 0u);
}

TEST(DetailTransferNode, RefusesAWalkOfAnotherLoop) {
  const Source s = bumpSource();
  auto encoding = std::make_shared<const DetailEncoding>(encode(s.featureUv, s.baseUv));
  auto walk = std::make_shared<SurfacePath>(walkTo(
      s.mesh, *s.baseUv,
      [&](const Eigen::Vector2d& u) { return DomainLocator(*s.featureUv).locate(u).point; }, 1.0));
  const NodeType* type = test::registry().find("geobrush.detail_transfer");
  ASSERT_NE(type, nullptr);
  test::DirectContext ctx(*type, {{"encoding", encoding},
                                  {"target_feature", s.featureUv},
                                  {"target_base", s.baseUv},
                                  {"walk", walk}});
  test::run(type->create(), ctx);
  const auto pasted = std::dynamic_pointer_cast<const Mesh>(ctx.outputs.at("pasted"));
  ASSERT_NE(pasted, nullptr);
  EXPECT_EQ(pasted->surface.n_vertices(), s.feature->surface.n_vertices());

  walk->point.pop_back();
  walk->face.pop_back();
  test::DirectContext bad(*type, {{"encoding", encoding},
                                  {"target_feature", s.featureUv},
                                  {"target_base", s.baseUv},
                                  {"walk", walk}});
  try {
    test::run(type->create(), bad);
    FAIL() << "a walk of another loop was used";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'walk'");
  }
}

}  // namespace
}  // namespace geobrush
