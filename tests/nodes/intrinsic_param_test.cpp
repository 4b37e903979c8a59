#include "intrinsic_param.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
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
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using test::canvasOf;
using test::centroidFan;
using test::membraneBase;
using test::nearestFace;

// An n x n grid over [-1, 1]^2, its interior vertices moved by up to 0.15 of a cell in a fixed
// pattern; every diagonal runs the same way, so each one-ring is a convex hexagon. Points are
// (x, y, 0) mapped by `rigid`; `plane` gets the (x, y) of each vertex.
MeshPtr jitteredGrid(int n, const Eigen::Isometry3d& rigid, std::vector<Vector2d>* plane) {
  TriMesh mesh;
  const double cell = 2.0 / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      Vector2d p(-1 + cell * i, -1 + cell * j);
      if (i > 0 && j > 0 && i < n && j < n)
        p += 0.15 * cell * Vector2d(std::sin(12.9898 * i + 78.233 * j), std::cos(4.1 * i * j + j));
      if (plane) plane->push_back(p);
      const Vector3d x = rigid * Vector3d(p.x(), p.y(), 0);
      mesh.add_vertex(toPoint(x));
    }
  const auto id = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return std::make_shared<const Mesh>(mesh);
}

std::vector<int> allFaces(const TriMesh& mesh) {
  std::vector<int> faces(mesh.n_faces());
  std::iota(faces.begin(), faces.end(), 0);
  return faces;
}

// The largest distance between `uv` and `expected` after the best rigid (or similarity) motion.
double fitResidual(const std::vector<Vector2d>& uv, const std::vector<Vector2d>& expected,
                   bool withScale, double* scale = nullptr) {
  Eigen::Matrix2Xd from(2, uv.size()), to(2, uv.size());
  for (std::size_t k = 0; k < uv.size(); ++k) {
    from.col(Eigen::Index(k)) = uv[k];
    to.col(Eigen::Index(k)) = expected[k];
  }
  const Eigen::Matrix3d map = fitSimilarity2d(uv, expected, withScale);
  if (scale) *scale = std::sqrt(map.topLeftCorner<2, 2>().determinant());
  return ((map.topLeftCorner<2, 2>() * from).colwise() + map.topRightCorner<2, 1>().eval() - to)
      .colwise()
      .norm()
      .maxCoeff();
}

double signedArea(const std::vector<Vector2d>& uv, const TriMesh& mesh, TriMesh::FaceHandle f) {
  std::vector<Vector2d> c;
  for (auto v : mesh.fv_range(f))
    c.push_back(uv[v.idx()]);
  const Vector2d a = c[1] - c[0], b = c[2] - c[0];
  return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

// Faces turned over, or degenerate (zero area to rounding) with a corner off the boundary: the
// convex hull lays a face whose three corners are boundary vertices on one side of the hull flat,
// and only such a face may be.
int clockwiseFaces(const std::vector<Vector2d>& uv, const TriMesh& mesh) {
  Eigen::AlignedBox2d box;
  for (const auto& p : uv)
    box.extend(p);
  const double rounding = 1e-12 * box.diagonal().squaredNorm();
  int count = 0;
  for (auto f : mesh.faces()) {
    bool onBoundary = true;
    for (auto v : mesh.fv_range(f))
      onBoundary = onBoundary && mesh.is_boundary(v);
    const double area = signedArea(uv, mesh, f);
    count += area < -rounding || (area <= rounding && !onBoundary) ? 1 : 0;
  }
  return count;
}

Eigen::Isometry3d tilted() {
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.rotate(Eigen::AngleAxisd(0.7, Vector3d(1, 2, -0.5).normalized()));
  rigid.pretranslate(Vector3d(3, -1, 2));
  return rigid;
}

TEST(IntrinsicParam, LinearPrecisionOnAPlanarMeshForAnyLambdaAndMu) {
  std::vector<Vector2d> plane;
  const MeshPtr mesh = jitteredGrid(8, tilted(), &plane);
  const CanvasPtr feature = canvasOf(mesh, allFaces(mesh->surface));
  const MeshPtr base = centroidFan(*feature);
  for (const auto& [lambda, mu] :
       std::vector<std::pair<double, double>>{{0.5, 0.5}, {1, 0}, {0, 1}, {0.2, 3}}) {
    IntrinsicParamOptions options;
    options.lambda = lambda;
    options.mu = mu;
    const IntrinsicParamResult r = intrinsicParameterize(*feature, base->surface, options);
    std::vector<Vector2d> expected;  // the canvas keeps the grid's vertex order (one region)
    for (int v = 0; v < int(feature->surface.n_vertices()); ++v)
      expected.push_back(plane[feature->sourceVertex[v]]);
    EXPECT_LT(fitResidual(r.featureUv, expected, false), 1e-9) << lambda << " " << mu;
    EXPECT_EQ(clockwiseFaces(r.featureUv, feature->surface), 0);
    EXPECT_EQ(clockwiseFaces(r.baseUv, base->surface), 0);
    // B's centroid, in the same plane, is reproduced too.
    for (int i = 0; i < int(feature->boundary.size()); ++i)
      EXPECT_EQ(r.baseUv[i], r.featureUv[feature->boundary[i]]);
    EXPECT_EQ(r.outsideVertices, 0);
  }
}

TEST(IntrinsicParam, PlaneModeUvIsTheProjectionAboutTheBoundaryCentroid) {
  std::vector<Vector2d> plane;
  const MeshPtr mesh = jitteredGrid(6, tilted(), &plane);
  const CanvasPtr feature = canvasOf(mesh, allFaces(mesh->surface));
  IntrinsicParamOptions planeMode;
  planeMode.boundary = BoundaryMode::Plane;
  const IntrinsicParamResult r =
      intrinsicParameterize(*feature, centroidFan(*feature)->surface, planeMode);
  const Vector3d normal = tilted().linear() * Vector3d::UnitZ();
  EXPECT_NEAR(r.plane.normal.dot(normal), 1.0, 1e-12);  // the faces' side: +z of the grid
  EXPECT_NEAR(r.plane.uAxis.cross(r.plane.vAxis).dot(r.plane.normal), 1.0, 1e-12);
  for (auto v : feature->surface.vertices()) {
    const Vector3d x = pointOf(feature->surface, v.idx());
    const Vector3d back = r.origin.point + r.featureUv[v.idx()].x() * r.origin.uAxis +
                          r.featureUv[v.idx()].y() * r.origin.vAxis;
    EXPECT_LT((back - x).norm(), 1e-12) << v.idx();
  }
  EXPECT_EQ(r.rotation, 0.0);
  EXPECT_EQ(r.scale, 1.0);
}

TEST(IntrinsicParam, LeastSquaresConformalMapReproducesAPlanarDiscWithAFreeBoundary) {
  std::vector<Vector2d> plane;
  const MeshPtr mesh = jitteredGrid(7, tilted(), &plane);
  const std::vector<Vector2d> uv = leastSquaresConformalMap(mesh->surface, 0, 63, "base");
  EXPECT_EQ(uv[0], Vector2d(0, 0));
  EXPECT_NEAR(uv[63].x(), (plane[63] - plane[0]).norm(), 1e-12);
  double scale = 0;
  EXPECT_LT(fitResidual(uv, plane, true, &scale), 1e-9);
  EXPECT_NEAR(scale, 1.0, 1e-9);
  EXPECT_EQ(clockwiseFaces(uv, mesh->surface), 0);
}

TEST(IntrinsicParam, NaturalModeReproducesAPlanarDiscUpToASimilarity) {
  std::vector<Vector2d> plane;
  const MeshPtr mesh = jitteredGrid(8, tilted(), &plane);
  const CanvasPtr feature = canvasOf(mesh, allFaces(mesh->surface));
  const MeshPtr base = centroidFan(*feature, {0, 5, 17});
  IntrinsicParamOptions options;
  options.boundary = BoundaryMode::Natural;
  const IntrinsicParamResult r = intrinsicParameterize(*feature, base->surface, options);
  std::vector<Vector2d> expected;
  for (int v = 0; v < int(feature->surface.n_vertices()); ++v)
    expected.push_back(plane[feature->sourceVertex[v]]);
  double scale = 0;
  EXPECT_LT(fitResidual(r.featureUv, expected, true, &scale), 1e-9);
  EXPECT_NEAR(scale, 1.0, 1e-9);  // pinned at their distance: no shrinking
  EXPECT_EQ(r.used, BoundaryMode::Natural);
  EXPECT_EQ(clockwiseFaces(r.baseUv, base->surface), 0);
}

TEST(IntrinsicParam, ConvexHullPlacesTheOtherPointsAtTheirChordLengthShare) {
  const std::vector<Vector2d> loop{{0, 0}, {2, 0}, {2, 2}, {1, 1.5}, {0.5, 1.75}, {0, 2}};
  const std::vector<Vector2d> placed = placeOnConvexHull(loop);
  for (int i : {0, 1, 2, 5})
    EXPECT_EQ(placed[i], loop[i]);
  // From (2, 2) to (0, 2) along the loop: lengths sqrt(1.25), then sqrt(0.3125), sqrt(0.3125).
  const double a = std::sqrt(1.25), b = std::sqrt(0.3125);
  EXPECT_LT((placed[3] - Vector2d(2 - 2 * a / (a + 2 * b), 2)).norm(), 1e-15);
  EXPECT_LT((placed[4] - Vector2d(2 - 2 * (a + b) / (a + 2 * b), 2)).norm(), 1e-15);
  // The same loop run the other way round gives the same points.
  std::vector<Vector2d> reversed(loop.rbegin(), loop.rend());
  const std::vector<Vector2d> placedBack = placeOnConvexHull(reversed);
  for (std::size_t i = 0; i < loop.size(); ++i)
    EXPECT_LT((placedBack[loop.size() - 1 - i] - placed[i]).norm(), 1e-15);
}

TEST(IntrinsicParam, InsidePolygonFollowsTheWindingAndTheTolerance) {
  const std::vector<Vector2d> c{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 2}, {3, 2}, {3, 3}, {0, 3}};
  EXPECT_TRUE(insidePolygon(c, {0.5, 1.5}, 0));
  EXPECT_FALSE(insidePolygon(c, {2, 1.5}, 0));  // in the notch
  EXPECT_TRUE(insidePolygon(c, {2, 1 + 1e-10}, 1e-9));
  EXPECT_FALSE(insidePolygon(c, {-0.1, 1}, 1e-9));
}

TEST(IntrinsicParam, FrameAlignmentMatchesAKnownSimilarity) {
  std::vector<Vector2d> plane;
  const MeshPtr mesh = jitteredGrid(10, tilted(), &plane);
  // F is the middle of the grid; the frame covers the whole of it.
  std::vector<int> middle;
  for (auto f : mesh->surface.faces()) {
    Vector2d c = Vector2d::Zero();
    for (auto v : mesh->surface.fv_range(f))
      c += plane[v.idx()] / 3;
    if (c.cwiseAbs().maxCoeff() < 0.55) middle.push_back(f.idx());
  }
  const CanvasPtr feature = canvasOf(mesh, middle);
  auto frame = std::make_shared<Parameterization>();
  frame->canvas = canvasOf(mesh, allFaces(mesh->surface));
  const Eigen::Rotation2Dd turn(2.1);
  const Vector2d shift(0.4, -1.3);
  const double scale = 1.7;
  for (int v : frame->canvas->sourceVertex)
    frame->uv.push_back(scale * (turn * plane[v]) + shift);
  frame->origin.point = Vector3d(1, 2, 3);
  frame->rotation = 0.25;
  frame->scale = 1 / scale;
  IntrinsicParamOptions options;
  options.frame = frame.get();
  const MeshPtr base = centroidFan(*feature);
  const IntrinsicParamResult r = intrinsicParameterize(*feature, base->surface, options);
  double worst = 0;
  for (auto v : feature->surface.vertices())
    worst = std::max(worst, (r.featureUv[v.idx()] -
                             (scale * (turn * plane[feature->sourceVertex[v.idx()]]) + shift))
                                .norm());
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(r.origin.point, frame->origin.point);
  EXPECT_EQ(r.rotation, 0.25);
  EXPECT_EQ(r.scale, 1 / scale);
  for (int i = 0; i < int(feature->boundary.size()); ++i)
    EXPECT_EQ(r.baseUv[i], r.featureUv[feature->boundary[i]]);
}

// F's boundary uv and B's agree bit for bit in every mode; B's split points sit on their chords.
void expectSharedBoundary(const Canvas& feature, const TriMesh& base,
                          const IntrinsicParamResult& r) {
  const int n = int(feature.boundary.size());
  for (int i = 0; i < n; ++i)
    ASSERT_EQ(r.baseUv[i], r.featureUv[feature.boundary[i]]) << i;
  for (auto h : base.halfedges()) {
    if (!base.is_boundary(h)) continue;
    const int v = base.to_vertex_handle(h).idx();
    if (v < n) continue;
    const int from = base.from_vertex_handle(h).idx();
    const int to = base.to_vertex_handle(base.next_halfedge_handle(h)).idx();
    const Vector2d chord = r.baseUv[to] - r.baseUv[from], rel = r.baseUv[v] - r.baseUv[from];
    EXPECT_LT(std::abs(chord.x() * rel.y() - chord.y() * rel.x()), 1e-12 * chord.squaredNorm());
    EXPECT_NEAR(rel.norm() / chord.norm(),
                (pointOf(base, v) - pointOf(base, from)).norm() /
                    (pointOf(base, to) - pointOf(base, from)).norm(),
                1e-12);
  }
}

MeshPtr readShared(const std::string& name) {
  return readMesh(test::meshPath(name)).mesh;
}

TEST(IntrinsicParam, BunnyDiscHasNoFlippedBaseFacesAndOneBoundaryInEveryMode) {
  const MeshPtr bunny = readShared("bunny_small.obj");
  const auto feature = std::make_shared<const Canvas>(
      test::growDiscCanvas(bunny, nearestFace(bunny->surface, Vector3d(0, 5, 4)), 2.5));
  ASSERT_GT(feature->surface.n_vertices(), 50u);
  const MeshPtr base = membraneBase(*feature, 50, {1, 2, 7});
  for (BoundaryMode mode :
       {BoundaryMode::Plane, BoundaryMode::Natural, BoundaryMode::ConvexHull, BoundaryMode::Auto}) {
    IntrinsicParamOptions options;
    options.boundary = mode;
    const IntrinsicParamResult r = intrinsicParameterize(*feature, base->surface, options);
    SCOPED_TRACE(int(mode));
    expectSharedBoundary(*feature, base->surface, r);
    EXPECT_EQ(clockwiseFaces(r.baseUv, base->surface), 0);
    EXPECT_EQ(std::count(r.baseFlipped.begin(), r.baseFlipped.end(), 1), 0);
    EXPECT_EQ(r.outsideVertices, 0);
    for (const auto& n : r.featureNormal)
      EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  }
}

// A tent: a C-shaped loop in the plane z = 0 (an annulus arc of 300 degrees) and one apex high
// over its centre, joined to every loop vertex. The apex projects into the C's gap.
MeshPtr tentOverC(int arcPoints) {
  TriMesh mesh;
  const double open = 300.0 * M_PI / 180.0;
  std::vector<Vector3d> loop;
  for (int k = 0; k < arcPoints; ++k) {  // outer arc, counter-clockwise
    const double t = open * k / (arcPoints - 1);
    loop.emplace_back(2 * std::cos(t), 2 * std::sin(t), 0);
  }
  for (int k = arcPoints - 1; k >= 0; --k) {  // inner arc, back
    const double t = open * k / (arcPoints - 1);
    loop.emplace_back(1.4 * std::cos(t), 1.4 * std::sin(t), 0);
  }
  for (const auto& p : loop)
    mesh.add_vertex(toPoint(p));
  const auto apex = mesh.add_vertex({0.3, 0.2, 6});
  const int n = int(loop.size());
  for (int i = 0; i < n; ++i)  // boundary halfedges i -> i + 1
    mesh.add_face(apex, TriMesh::VertexHandle((i + 1) % n), TriMesh::VertexHandle(i));
  return std::make_shared<const Mesh>(mesh);
}

// The C strip: quads between the outer arc and the inner arc, faces as the loop's (c, b, a).
MeshPtr stripBase(const Canvas& feature, int arcPoints) {
  TriMesh base;
  for (int v : feature.boundary) {
    const Vector3d p = pointOf(feature.surface, v);
    base.add_vertex(toPoint(p));
  }
  const int last = 2 * arcPoints - 1;
  const auto face = [&](int a, int b, int c) {  // a < b < c in loop order
    base.add_face(TriMesh::VertexHandle(c), TriMesh::VertexHandle(b), TriMesh::VertexHandle(a));
  };
  for (int k = 0; k + 1 < arcPoints; ++k) {
    face(k, k + 1, last - k);
    face(k + 1, last - k - 1, last - k);
  }
  return std::make_shared<const Mesh>(base);
}

TEST(IntrinsicParam, AutoSwitchesToTheConvexHullWhenFLeavesAConcaveBoundary) {
  const MeshPtr tent = tentOverC(12);
  const CanvasPtr feature = canvasOf(tent, allFaces(tent->surface));
  ASSERT_EQ(feature->boundary.front(), 0);
  const MeshPtr base = stripBase(*feature, 12);
  IntrinsicParamOptions planeMode;
  planeMode.boundary = BoundaryMode::Plane;
  const IntrinsicParamResult plane = intrinsicParameterize(*feature, base->surface, planeMode);
  EXPECT_EQ(clockwiseFaces(plane.baseUv, base->surface), 0);
  EXPECT_EQ(plane.outsideVertices, 1);  // the apex, in the C's gap
  IntrinsicParamOptions options;
  options.boundary = BoundaryMode::Auto;
  const IntrinsicParamResult r = intrinsicParameterize(*feature, base->surface, options);
  EXPECT_EQ(r.used, BoundaryMode::ConvexHull);
  EXPECT_EQ(r.planeOutsideVertices, 1);
  EXPECT_EQ(r.outsideVertices, 0);
  expectSharedBoundary(*feature, base->surface, r);

  const NodeType* type = test::registry().find("geobrush.intrinsic_param");
  ASSERT_NE(type, nullptr);
  test::DirectContext ctx(*type, {{"feature", feature}, {"base", base}},
                          {{"boundary", std::string("auto")}});
  test::run(type->create(), ctx);
  ASSERT_GE(ctx.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(ctx.warnings[0], "switched from plane to convex_hull"))
      << ctx.warnings[0];
}

TEST(IntrinsicParamNode, OutputsBothParameterizationsOverTheirCanvases) {
  const MeshPtr mountain = readShared("mountain.obj");
  const auto feature = std::make_shared<const Canvas>(test::growDiscCanvas(
      mountain, nearestFace(mountain->surface, Vector3d(1.1, 24.9, 2.5)), 3.0));
  const MeshPtr base = membraneBase(*feature, 50, {0, 3});
  const NodeType* type = test::registry().find("geobrush.intrinsic_param");
  ASSERT_NE(type, nullptr);
  test::DirectContext ctx(*type, {{"feature", feature}, {"base", base}});
  test::run(type->create(), ctx);
  const auto pf = std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["feature"]);
  const auto pb = std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["base"]);
  ASSERT_TRUE(pf && pb);
  EXPECT_EQ(pf->canvas, feature);
  EXPECT_EQ(pb->canvas->source, base);
  EXPECT_EQ(pb->canvas->boundary.size(), feature->boundary.size() + 2);
  ASSERT_EQ(pf->uv.size(), feature->surface.n_vertices());
  ASSERT_EQ(pb->uv.size(), base->surface.n_vertices());
  for (int i = 0; i < int(feature->boundary.size()); ++i)
    EXPECT_EQ(pb->uv[i], pf->uv[feature->boundary[i]]);
  EXPECT_EQ(clockwiseFaces(pb->uv, base->surface), 0);
  EXPECT_EQ(clockwiseFaces(pf->uv, feature->surface), 0);  // a height field: an embedding
  EXPECT_GT(pf->normal[0].y(), 0.5);                       // +y is up on the mountain
  EXPECT_GT(pf->origin.normal.y(), 0.9);
  EXPECT_TRUE(ctx.warnings.empty());
  test::DirectContext again(*type, {{"feature", feature}, {"base", base}});
  test::run(type->create(), again);
  EXPECT_EQ(again.outputs["feature"]->contentHash(), pf->contentHash());
  EXPECT_EQ(again.outputs["base"]->contentHash(), pb->contentHash());
}

NodeError failure(const NodeType& type, const std::map<std::string, ValuePtr, std::less<>>& in,
                  const ParamMap& params = {}) {
  test::DirectContext ctx(type, in, params);
  try {
    test::run(type.create(), ctx);
  } catch (const NodeError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted";
  return NodeError("");
}

TEST(IntrinsicParamNode, RefusesABaseOffTheConventionAndAFrameWithoutMatches) {
  const MeshPtr mesh = jitteredGrid(6, Eigen::Isometry3d::Identity(), nullptr);
  const CanvasPtr feature = canvasOf(mesh, allFaces(mesh->surface));
  const NodeType& type = *test::registry().find("geobrush.intrinsic_param");
  const MeshPtr base = centroidFan(*feature);

  TriMesh moved = base->surface;
  moved.set_point(TriMesh::VertexHandle(3),
                  moved.point(TriMesh::VertexHandle(3)) + OpenMesh::Vec3d(0, 0, 1e-3));
  NodeError e =
      failure(type, {{"feature", feature}, {"base", std::make_shared<const Mesh>(moved)}});
  EXPECT_EQ(e.where(), "input 'base'");
  EXPECT_TRUE(test::contains(e.what(), "vertex 3"));

  TriMesh reversed;  // the same fan, faces turned over
  for (auto v : base->surface.vertices())
    reversed.add_vertex(base->surface.point(v));
  for (auto f : base->surface.faces()) {
    std::vector<TriMesh::VertexHandle> c;
    for (auto v : base->surface.fv_range(f))
      c.push_back(v);
    reversed.add_face(c[2], c[1], c[0]);
  }
  e = failure(type, {{"feature", feature}, {"base", std::make_shared<const Mesh>(reversed)}});
  EXPECT_EQ(e.where(), "input 'base'");
  EXPECT_TRUE(test::contains(e.what(), "oriented like F's"));

  auto frame = std::make_shared<Parameterization>();
  frame->canvas = canvasOf(mesh, {0});  // one corner face: two of its vertices on F's boundary
  frame->uv.assign(frame->canvas->surface.n_vertices(), Vector2d::Zero());
  for (std::size_t v = 0; v < frame->uv.size(); ++v)
    frame->uv[v] = Vector2d(double(v), double(v * v));
  e = failure(type, {{"feature", feature}, {"base", base}, {"frame", frame}});
  EXPECT_EQ(e.where(), "input 'frame'");
  EXPECT_TRUE(test::contains(e.what(), "3 are needed"));

  e = failure(type, {{"feature", feature}, {"base", base}}, {{"lambda", 0.0}, {"mu", 0.0}});
  EXPECT_EQ(e.where(), "param 'mu'");
}

}  // namespace
}  // namespace geobrush
