#include "detail_encode.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <vector>

#include "base_fixtures.hpp"
#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/cut_paste.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using test::canvasOf;
using test::centroidFan;
using test::membraneBase;
using test::nearestFace;

// An n x n grid over [-1, 1]^2 at (x + shift(x, y), y, height(x, y)), mapped by `rigid`.
MeshPtr grid(int n, const std::function<double(double, double)>& height,
             const std::function<double(double, double)>& shift,
             const Eigen::Isometry3d& rigid = Eigen::Isometry3d::Identity()) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      const Vector3d p = rigid * Vector3d(x + shift(x, y), y, height(x, y));
      mesh.add_vertex(toPoint(p));
    }
  const auto id = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return std::make_shared<const Mesh>(mesh);
}

double zero(double, double) {
  return 0.0;
}

CanvasPtr wholeCanvas(const MeshPtr& mesh) {
  std::vector<int> faces(mesh->surface.n_faces());
  std::iota(faces.begin(), faces.end(), 0);
  return canvasOf(mesh, faces);
}

// uv = (x, y) of each vertex, normals +z: the parameterization of a height field over z = 0.
ParameterizationPtr projection(CanvasPtr canvas) {
  auto p = std::make_shared<Parameterization>();
  p->canvas = std::move(canvas);
  for (auto v : p->canvas->surface.vertices()) {
    const Vector3d x = pointOf(p->canvas->surface, v.idx());
    p->uv.emplace_back(x.x(), x.y());
    p->normal.push_back(Vector3d::UnitZ());
  }
  return p;
}

ParameterizationPtr baseProjection(const MeshPtr& base) {
  return projection(std::make_shared<const Canvas>(canvasOfMesh(base)));
}

struct Params {
  ParameterizationPtr feature, base;
};

// P^F and P^B from the intrinsic_param node.
Params intrinsicParams(const CanvasPtr& feature, const MeshPtr& base) {
  const NodeType* type = test::registry().find("geobrush.intrinsic_param");
  EXPECT_NE(type, nullptr);
  test::DirectContext ctx(*type, {{"feature", feature}, {"base", base}});
  test::run(type->create(), ctx);
  return {std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["feature"]),
          std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["base"])};
}

// The largest distance between a decoded vertex and F's, over F's bounding diagonal.
double relativeDecodeError(const DetailEncoding& encoding) {
  const TriMesh& f = encoding.feature->canvas->surface;
  const std::vector<Vector3d> decoded = decodeOverOwnBase(encoding);
  double worst = 0;
  for (auto v : f.vertices())
    worst = std::max(worst, (decoded[v.idx()] - pointOf(f, v.idx())).norm());
  return worst / boundingDiagonal(f);
}

double largestOffset(const DetailEncoding& encoding) {
  double largest = 0;
  for (const auto& c : encoding.offset)
    largest = std::max(largest, c.norm());
  return largest;
}

// F.boundary[i] sits exactly on B's vertex i with offset 0.
void expectBoundaryOnBaseVertices(const DetailEncoding& e) {
  const Canvas& f = *e.feature->canvas;
  const TriMesh& b = e.base->canvas->surface;
  for (int i = 0; i < int(f.boundary.size()); ++i) {
    const int v = f.boundary[i];
    EXPECT_EQ(e.offset[v], Vector3d::Zero());
    int corner = -1, k = 0;
    for (auto w : b.fv_range(TriMesh::FaceHandle(e.baseFace[v])))
      corner = w.idx() == i ? k++ : (k++, corner);
    ASSERT_GE(corner, 0) << i;
    EXPECT_EQ(e.barycentric[v], Vector3d::Unit(corner)) << i;
  }
}

Eigen::Isometry3d tilted() {
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.rotate(Eigen::AngleAxisd(0.9, Vector3d(-1, 2, 0.5).normalized()));
  rigid.pretranslate(Vector3d(-2, 1, 4));
  return rigid;
}

TEST(DetailEncode, AFlatFeatureHasNoOffsets) {
  const MeshPtr plane = grid(
      9, zero, [](double x, double y) { return 0.05 * std::sin(7 * x * y); }, tilted());
  const CanvasPtr feature = wholeCanvas(plane);
  const Params p = intrinsicParams(feature, centroidFan(*feature));
  const double diagonal = boundingDiagonal(feature->surface);
  for (DetailMethod method :
       {DetailMethod::FaceFrame, DetailMethod::SmoothFrame, DetailMethod::NormalDisplacement}) {
    const DetailEncoding e = encodeDetail(p.feature, p.base, method);
    EXPECT_LT(largestOffset(e), 1e-12 * diagonal);
    EXPECT_LT(relativeDecodeError(e), 1e-12);
    expectBoundaryOnBaseVertices(e);
  }
}

double bump(double x, double y) {
  return 0.3 * (1 - x * x) * (1 - y * y);
}
double slide(double x, double y) {
  return 0.2 * (1 - x * x) * (1 - y * y) * std::cos(2 * y);
}

TEST(DetailEncode, AHeightFieldOverAPlaneIsItsHeightForBothMethods) {
  const MeshPtr field = grid(10, bump, zero);
  const CanvasPtr feature = wholeCanvas(field);
  const MeshPtr base = centroidFan(*feature);
  const ParameterizationPtr pf = projection(feature), pb = baseProjection(base);
  for (DetailMethod method :
       {DetailMethod::FaceFrame, DetailMethod::SmoothFrame, DetailMethod::NormalDisplacement}) {
    const DetailEncoding e = encodeDetail(pf, pb, method);
    for (auto v : feature->surface.vertices()) {
      const Vector3d x = pointOf(feature->surface, v.idx());
      EXPECT_NEAR(e.offset[v.idx()].z(), bump(x.x(), x.y()), 1e-15);
      EXPECT_NEAR(e.offset[v.idx()].head<2>().norm(), 0, 1e-15);
    }
    EXPECT_LT(relativeDecodeError(e), 1e-9);
  }
}

TEST(DetailEncode, ATangentialOffsetIsKeptByFramesAndLostByNormalDisplacement) {
  // The vertices slide along x by `slide`, while their uv stay at the unslid (x, y).
  const MeshPtr field = grid(10, bump, slide);
  const CanvasPtr feature = wholeCanvas(field);
  const MeshPtr base = centroidFan(*feature);
  auto pf = std::make_shared<Parameterization>(*projection(feature));
  const int n = 10;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      pf->uv[feature->sourceVertex[j * (n + 1) + i]] = Vector2d(-1 + 0.2 * i, -1 + 0.2 * j);
  const ParameterizationPtr pb = baseProjection(base);
  for (DetailMethod method : {DetailMethod::FaceFrame, DetailMethod::SmoothFrame})
    EXPECT_LT(relativeDecodeError(encodeDetail(pf, pb, method)), 1e-9);
  const DetailEncoding normal = encodeDetail(pf, pb, DetailMethod::NormalDisplacement);
  const std::vector<Vector3d> decoded = decodeOverOwnBase(normal);
  double lost = 0;
  for (auto v : feature->surface.vertices()) {
    const Vector3d x = pointOf(feature->surface, v.idx());
    const Vector2d uv = pf->uv[v.idx()];
    EXPECT_LT((decoded[v.idx()] - Vector3d(uv.x(), uv.y(), x.z())).norm(), 1e-12);
    lost = std::max(lost, std::abs(slide(uv.x(), uv.y())));
  }
  EXPECT_GT(lost, 0.15);
  EXPECT_NEAR(relativeDecodeError(normal) * boundingDiagonal(feature->surface), lost, 1e-12);
}

// A feature vertex whose uv falls outside the base (or onto a face the domain lays flat) is not
// extrapolated: its coordinates are clamped onto its face and the offset takes up the rest, so it
// still decodes to itself and stays bounded over a moved base.
TEST(DetailEncode, AVertexOutsideTheBaseIsClampedOntoItsFaceAndStillDecodes) {
  const MeshPtr field = grid(10, bump, zero);
  const CanvasPtr feature = wholeCanvas(field);
  auto pf = std::make_shared<Parameterization>(*projection(feature));
  const int inside = feature->sourceVertex[5 * 11 + 5];  // the grid's middle vertex
  pf->uv[std::size_t(inside)] = Vector2d(3.0, 0.2);      // far outside the base's square
  const ParameterizationPtr pb = baseProjection(centroidFan(*feature));
  for (DetailMethod method : {DetailMethod::FaceFrame, DetailMethod::SmoothFrame}) {
    const DetailEncoding e = encodeDetail(pf, pb, method);
    for (const Vector3d& b : e.barycentric) {
      EXPECT_GE(b.minCoeff(), 0.0);
      EXPECT_NEAR(b.sum(), 1.0, 1e-15);
    }
    EXPECT_LT(relativeDecodeError(e), 1e-9);
  }
}

MeshPtr readShared(const std::string& name) {
  return readMesh(test::meshPath(name)).mesh;
}

TEST(DetailEncode, AGenusOneFeatureDecodesToItself) {
  const MeshPtr torus = readShared("torus.obj");
  std::vector<int> kept;
  std::vector<char> removed(torus->surface.n_faces(), 0);
  for (auto f : torus->surface.vf_range(TriMesh::VertexHandle(0)))
    removed[f.idx()] = 1;
  for (int f = 0; f < int(removed.size()); ++f)
    if (!removed[f]) kept.push_back(f);
  const CanvasPtr feature = canvasOf(torus, kept);
  const test::Topology t = test::topology(feature->surface);
  ASSERT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.eulerCharacteristic, -1);  // 2 - 2 genus - loops: genus 1
  const Params p = intrinsicParams(feature, centroidFan(*feature));
  for (DetailMethod method : {DetailMethod::FaceFrame, DetailMethod::SmoothFrame}) {
    const DetailEncoding e = encodeDetail(p.feature, p.base, method);
    EXPECT_LT(relativeDecodeError(e), 1e-9);
    expectBoundaryOnBaseVertices(e);
  }
}

TEST(DetailEncode, BumpyRealFeaturesDecodeToThemselves) {
  const std::vector<std::tuple<std::string, Vector3d, double>> cases{
      {"mountain.obj", Vector3d(1.1, 24.9, 2.5), 3.0}, {"bunny_small.obj", Vector3d(0, 5, 4), 2.5}};
  for (const auto& [name, centre, radius] : cases) {
    SCOPED_TRACE(name);
    const MeshPtr mesh = readShared(name);
    const auto feature = std::make_shared<const Canvas>(
        test::growDiscCanvas(mesh, nearestFace(mesh->surface, centre), radius));
    const Params p = intrinsicParams(feature, membraneBase(*feature, 50, {0, 5}));
    for (DetailMethod method : {DetailMethod::FaceFrame, DetailMethod::SmoothFrame}) {
      const DetailEncoding frame = encodeDetail(p.feature, p.base, method);
      EXPECT_LT(relativeDecodeError(frame), 1e-9);
      EXPECT_GT(largestOffset(frame), 1e-3 * boundingDiagonal(feature->surface));  // bumpy
      expectBoundaryOnBaseVertices(frame);
    }
    // Normal displacement keeps only the heights: the tangential parts are lost.
    const DetailEncoding normal = encodeDetail(p.feature, p.base, DetailMethod::NormalDisplacement);
    EXPECT_GT(relativeDecodeError(normal), 1e-4);
  }
}

TEST(DetailEncodeNode, EncodesThroughTheNode) {
  const MeshPtr field = grid(6, bump, slide);
  const CanvasPtr feature = wholeCanvas(field);
  const MeshPtr base = centroidFan(*feature);
  const Params p = intrinsicParams(feature, base);
  const NodeType* type = test::registry().find("geobrush.detail_encode");
  ASSERT_NE(type, nullptr);
  const std::map<std::string, DetailMethod> methods{
      {"face_frame", DetailMethod::FaceFrame},
      {"smooth_frame", DetailMethod::SmoothFrame},
      {"normal_displacement", DetailMethod::NormalDisplacement}};
  for (const auto& [method, expected] : methods) {
    test::DirectContext ctx(*type, {{"feature", p.feature}, {"base", p.base}},
                            {{"method", method}});
    test::run(type->create(), ctx);
    const auto e = std::dynamic_pointer_cast<const DetailEncoding>(ctx.outputs["encoding"]);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->feature, p.feature);
    EXPECT_EQ(e->base, p.base);
    EXPECT_EQ(e->method, expected);
    ASSERT_EQ(e->offset.size(), feature->surface.n_vertices());
    const DetailEncoding direct = encodeDetail(p.feature, p.base, e->method);
    EXPECT_EQ(e->contentHash(), direct.contentHash());
  }
}

NodeError failure(const std::map<std::string, ValuePtr, std::less<>>& in) {
  const NodeType& type = *test::registry().find("geobrush.detail_encode");
  test::DirectContext ctx(type, in);
  try {
    test::run(type.create(), ctx);
  } catch (const NodeError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted";
  return NodeError("");
}

TEST(DetailEncodeNode, NamesThePortOfABadInput) {
  const MeshPtr field = grid(6, bump, zero);
  const CanvasPtr feature = wholeCanvas(field);
  const MeshPtr base = centroidFan(*feature);
  const ParameterizationPtr pf = projection(feature);

  TriMesh moved = base->surface;
  moved.set_point(TriMesh::VertexHandle(2),
                  moved.point(TriMesh::VertexHandle(2)) + OpenMesh::Vec3d(0, 1e-4, 0));
  NodeError e =
      failure({{"feature", pf}, {"base", baseProjection(std::make_shared<const Mesh>(moved))}});
  EXPECT_EQ(e.where(), "input 'base'");
  EXPECT_TRUE(test::contains(e.what(), "vertex 2"));

  TriMesh triangle;
  for (int k = 0; k < 3; ++k)
    triangle.add_vertex(base->surface.point(TriMesh::VertexHandle(k)));
  triangle.add_face(TriMesh::VertexHandle(0), TriMesh::VertexHandle(1), TriMesh::VertexHandle(2));
  e = failure({{"feature", pf}, {"base", baseProjection(std::make_shared<const Mesh>(triangle))}});
  EXPECT_EQ(e.where(), "input 'base'");
  EXPECT_TRUE(test::contains(e.what(), "fewer than F's 24 boundary vertices"));

  auto shortUv = std::make_shared<Parameterization>(*pf);
  shortUv->uv.pop_back();
  e = failure({{"feature", shortUv}, {"base", baseProjection(base)}});
  EXPECT_EQ(e.where(), "input 'feature'");
}

}  // namespace
}  // namespace geobrush
