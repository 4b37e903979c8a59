#include "base_optimize.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "base_mesh_ops.hpp"
#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

Vector3d at(const TriMesh& mesh, int v) {
  return pointOf(mesh, TriMesh::VertexHandle(v));
}

Vector3d faceNormal(const TriMesh& mesh, TriMesh::FaceHandle f) {
  std::vector<Vector3d> c;
  for (auto v : mesh.fv_range(f))
    c.push_back(at(mesh, v.idx()));
  return (c[1] - c[0]).cross(c[2] - c[0]);
}

Vector3d centroid(const TriMesh& mesh, TriMesh::FaceHandle f) {
  Vector3d sum = Vector3d::Zero();
  for (auto v : mesh.fv_range(f))
    sum += at(mesh, v.idx()) / 3;
  return sum;
}

// B0 by a fan from vertex 0 over `loop`, boundary halfedges running i -> i + 1.
TriMesh fanBase(const std::vector<Vector3d>& loop) {
  TriMesh mesh;
  for (const auto& p : loop)
    mesh.add_vertex(toPoint(p));
  for (int k = 1; k + 1 < int(loop.size()); ++k)
    mesh.add_face(TriMesh::VertexHandle(0), TriMesh::VertexHandle(k + 1), TriMesh::VertexHandle(k));
  return mesh;
}

// An ellipse with radii rx, ry in a tilted plane through (1, 2, 3); its unit normal in `normal`.
std::vector<Vector3d> tiltedEllipse(int n, double rx, double ry, Vector3d* normal) {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.7, Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
  *normal = turn * Vector3d::UnitZ();
  std::vector<Vector3d> loop;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n;
    loop.push_back(turn * Vector3d(rx * std::cos(angle), ry * std::sin(angle), 0) +
                   Vector3d(1, 2, 3));
  }
  return loop;
}

// The vertices met walking the boundary halfedges from vertex 0.
std::vector<int> boundaryWalk(const TriMesh& mesh) {
  std::vector<int> walk;
  const auto start = mesh.find_halfedge(TriMesh::VertexHandle(0), TriMesh::VertexHandle(1));
  auto h = start;
  if (!h.is_valid() || !mesh.is_boundary(h)) {
    // The loop may start with a point added on the chord 0-1: take vertex 0's boundary halfedge.
    for (auto out : mesh.voh_range(TriMesh::VertexHandle(0)))
      if (mesh.is_boundary(out)) h = out;
  }
  const auto first = h;
  do {
    walk.push_back(mesh.from_vertex_handle(h).idx());
    h = mesh.next_halfedge_handle(h);
  } while (h != first && walk.size() <= mesh.n_vertices());
  return walk;
}

// cut_paste.hpp's base convention: B0's vertices kept bit-identical in order, the loop walked
// 0, (points on chord 0-1), 1, ..., each added point on its chord between its ends and in order
// along it, a manifold disc; and Eq. 2: every edge shorter than `target`.
void expectBaseConvention(const TriMesh& b0, const TriMesh& b, double target) {
  const int n = checkedLoopLength(b0);
  ASSERT_GE(int(b.n_vertices()), n);
  for (int v = 0; v < n; ++v)
    ASSERT_EQ(b.point(TriMesh::VertexHandle(v)), b0.point(TriMesh::VertexHandle(v))) << v;
  const auto walk = boundaryWalk(b);
  int original = 0;
  double lastT = 0;
  for (std::size_t i = 0; i < walk.size(); ++i) {
    const int v = walk[i];
    if (v < n) {
      ASSERT_EQ(v, original) << "loop vertex out of order at step " << i;
      original = (original + 1) % n;
      lastT = 0;
      continue;
    }
    const Vector3d a = at(b, (original + n - 1) % n), c = at(b, original), p = at(b, v);
    const double t = (p - a).dot(c - a) / (c - a).squaredNorm();
    EXPECT_GT(t, lastT) << v;
    EXPECT_LT(t, 1.0) << v;
    EXPECT_LT((a + t * (c - a) - p).norm(), 1e-14 * (c - a).norm() + 1e-15) << v;
    lastT = t;
  }
  EXPECT_EQ(original, 0);  // the walk went round once
  const auto topo = test::topology(b);
  EXPECT_EQ(topo.boundaryLoops, 1u);
  EXPECT_EQ(topo.components, 1u);
  EXPECT_EQ(topo.nonManifoldVertices, 0u);
  EXPECT_EQ(topo.isolatedVertices, 0u);
  EXPECT_EQ(topo.eulerCharacteristic, 1);
  double longest = 0;
  for (double l : test::edgeLengths(b))
    longest = std::max(longest, l);
  EXPECT_LT(longest, target);
}

// Every face of B turns the way the nearest face of B0 (by centroid) does.
int facesFlippedAgainst(const TriMesh& b0, const TriMesh& b) {
  int flipped = 0;
  for (auto f : b.faces()) {
    const Vector3d c = centroid(b, f);
    TriMesh::FaceHandle nearest;
    double best = std::numeric_limits<double>::infinity();
    for (auto g : b0.faces())
      if (const double d = (centroid(b0, g) - c).norm(); d < best) {
        best = d;
        nearest = g;
      }
    flipped += faceNormal(b, f).dot(faceNormal(b0, nearest)) > 0 ? 0 : 1;
  }
  return flipped;
}

TEST(BaseOptimize, AspectRatiosOfKnownTriangles) {
  const Vector3d o(0, 0, 0), x(1, 0, 0), y(0, 1, 0);
  EXPECT_NEAR(aspectRatio(o, x, Vector3d(0.5, std::sqrt(3.0) / 2, 0)), std::sqrt(3.0) / 2, 1e-15);
  EXPECT_DOUBLE_EQ(aspectRatio(o, x, y), 1.0);                      // right isosceles
  EXPECT_DOUBLE_EQ(aspectRatio(o, x, Vector3d(0, 3, 0)), 1.0 / 3);  // its legs' rectangle
  // A cap of height h over its longest edge L, apex off centre.
  EXPECT_NEAR(aspectRatio(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), Vector3d(0.3, 0.05, 0)), 0.05 / 2,
              1e-15);
  EXPECT_EQ(aspectRatio(o, x, Vector3d(2, 0, 0)), 0.0);  // degenerate
  // Any order of the corners, any place in space.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(1.1, Vector3d(1, -1, 2).normalized()).matrix();
  EXPECT_NEAR(aspectRatio(turn * y, turn * o + Vector3d(4, 5, 6) - Vector3d(4, 5, 6), turn * x),
              1.0, 1e-15);
}

// A planar B0 stays in its plane: splits land on its edges, slices on its edges, collapses on
// an endpoint or a midpoint, and umbrella smoothing averages points of the plane.
TEST(BaseOptimize, APlanarFanBecomesADenseFlatDiscWithEveryEdgeBelowEq2) {
  Vector3d normal;
  const auto loop = tiltedEllipse(14, 3.0, 1.0, &normal);
  const TriMesh b0 = fanBase(loop);
  const auto result = optimizeBase(b0, BaseOptimizeOptions{});
  EXPECT_EQ(result.loopVertices, 14);
  EXPECT_DOUBLE_EQ(result.referenceLength, minimumEdgeLength(b0));
  EXPECT_DOUBLE_EQ(result.targetLength, 2.0 * result.referenceLength);
  expectBaseConvention(b0, result.base, result.targetLength);
  EXPECT_GT(result.base.n_vertices(), 60u);
  double offPlane = 0;
  for (auto v : result.base.vertices())
    offPlane = std::max(offPlane, std::abs((pointOf(result.base, v) - loop[0]).dot(normal)));
  EXPECT_LT(offPlane, 1e-12 * boundingDiagonal(result.base));
  EXPECT_EQ(facesFlippedAgainst(b0, result.base), 0);
  EXPECT_GT(result.minAngleAfterDeg, result.minAngleBeforeDeg);
  EXPECT_EQ(result.needlesLeft, countNeedles(result.base, 0.1));
  {
    std::ostringstream measured;
    measured << "planar fan: " << result.base.n_vertices() << " vertices, " << result.splits
             << " splits, " << result.slices << " slices, " << result.collapses
             << " collapses, min angle " << result.minAngleBeforeDeg << " -> "
             << result.minAngleAfterDeg << " deg, off plane " << offPlane << ", needles left "
             << result.needlesLeft;
    RecordProperty("measured", measured.str());
  }
}

// Steps 1-3 on the fan: splitting adds needles (halved fan sectors), slicing turns caps into
// needles, and the collapses leave none; smoothing (step 4) may make new ones at the fan's
// apex, whose sectors no step widens.
TEST(BaseOptimize, CollapsesLeaveNoNeedleInAPlanarFan) {
  Vector3d normal;
  TriMesh mesh = fanBase(tiltedEllipse(14, 3.0, 1.0, &normal));
  const double target = 2.0 * minimumEdgeLength(mesh);
  const int before = countNeedles(mesh, 0.1);
  splitLongEdges(mesh, target, 100000);
  const int split = countNeedles(mesh, 0.1);
  const int slices = sliceCaps(mesh, 160.0, 0.1, 100000);
  const int sliced = countNeedles(mesh, 0.1);
  const int collapses = collapseNeedles(mesh, 14, 0.1, target);
  const TriMesh b = compactBase(mesh, 14);
  EXPECT_GT(split, before);
  EXPECT_GT(slices, 0);
  EXPECT_GT(collapses, 0);
  EXPECT_EQ(countNeedles(b, 0.1), 0);
  for (double l : test::edgeLengths(b))
    EXPECT_LT(l, target);
  {
    std::ostringstream measured;
    measured << "needles: B0 " << before << ", split " << split << ", sliced " << sliced
             << ", collapsed 0 (" << slices << " slices, " << collapses << " collapses)";
    RecordProperty("measured", measured.str());
  }
}

// A cap (apex angle 175 deg) over an interior edge: slicing splits that edge at the apex's foot,
// the collapse of the foot into the apex then leaves the flipped diagonal (Botsch-Kobbelt).
TEST(BaseOptimize, SlicingACapAndCollapseItsNeedlesFlipsTheDiagonal) {
  const double h = std::tan(2.5 * M_PI / 180);
  const std::vector<Vector3d> loop{{-1, 0, 0}, {0, -1, 0}, {1, 0, 0}, {0, h, 0}};
  const TriMesh b0 = fanBase(loop);  // faces (0, 2, 1) and (0, 3, 2): the cap over edge 0-2
  BaseOptimizeOptions options;
  options.epsilon = 10;  // no split
  const auto result = optimizeBase(b0, options);
  EXPECT_EQ(result.splits, 0);
  EXPECT_EQ(result.slices, 1);
  EXPECT_EQ(result.collapses, 1);
  ASSERT_EQ(result.base.n_vertices(), 4u);
  EXPECT_EQ(result.base.n_faces(), 2u);
  EXPECT_TRUE(
      result.base.find_halfedge(TriMesh::VertexHandle(1), TriMesh::VertexHandle(3)).is_valid());
  EXPECT_FALSE(
      result.base.find_halfedge(TriMesh::VertexHandle(0), TriMesh::VertexHandle(2)).is_valid());
  expectBaseConvention(b0, result.base, options.epsilon * minimumEdgeLength(b0));
  EXPECT_EQ(facesFlippedAgainst(b0, result.base), 0);
  EXPECT_NEAR(result.minAngleBeforeDeg, 2.5, 1e-12);
  EXPECT_NEAR(result.minAngleAfterDeg, 45.0, 1e-12);  // at vertex 1 of face (0, 1, 3)
}

// Midpoint splits halve boundary edges exactly: a chord of length L gets 2^k - 1 points.
TEST(BaseOptimize, SplittingHalvesBoundaryEdgesUntilEq2Holds) {
  const std::vector<Vector3d> loop{{0, 0, 0}, {8, 0, 0}, {8, 1, 0}, {0, 1, 0}};
  TriMesh mesh = fanBase(loop);
  const int splits = splitLongEdges(mesh, 1.5, 1000);
  EXPECT_EQ(splits, int(mesh.n_vertices()) - 4);
  for (auto e : mesh.edges())
    EXPECT_LT(edgeLength(mesh, e), 1.5);
  int boundaryVertices = 0;
  for (auto v : mesh.vertices())
    boundaryVertices += mesh.is_boundary(v) ? 1 : 0;
  EXPECT_EQ(boundaryVertices, 4 + 2 * 7);  // long sides in 8 pieces of 1, short ones whole
  // 18 boundary vertices and at least 8 / (sqrt(3) / 4 1.5^2) faces: V >= (F + 18) / 2 + 1.
  EXPECT_DOUBLE_EQ(vertexLowerBound(fanBase(loop), 1.5),
                   (8.0 / (std::sqrt(3.0) / 4 * 2.25) + 18) / 2 + 1);
  EXPECT_LE(vertexLowerBound(fanBase(loop), 1.5), double(mesh.n_vertices()));
  TriMesh again = fanBase(loop);
  EXPECT_THROW(splitLongEdges(again, 1.5, 10), BaseGrowthError);
}

const NodeType& nodeType(const std::string& id) {
  const NodeType* type = test::registry().find(id);
  EXPECT_NE(type, nullptr) << id;
  return *type;
}

// B0 of a canvas on a shared mesh, through the min_area_triangulate node.
MeshPtr realBase(const std::string& file, const Vector3d& near, double radius) {
  const MeshPtr mesh = readMesh(test::meshPath(file)).mesh;
  const TriMesh& m = mesh->surface;
  int nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (auto f : m.faces())
    if (const double d = (centroid(m, f) - near).norm(); d < best) {
      best = d;
      nearest = f.idx();
    }
  auto canvas = std::make_shared<const Canvas>(test::growDiscCanvas(mesh, nearest, radius));
  const auto& type = nodeType("geobrush.min_area_triangulate");
  test::DirectContext ctx(type, {{"canvas", canvas}});
  type.create()->compute(ctx);
  auto base = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["base"]);
  EXPECT_TRUE(base);
  return base;
}

struct NodeRun {
  MeshPtr base;
  std::shared_ptr<const Metrics> report;
  std::vector<std::string> warnings;
};

NodeRun optimizeThroughNode(const MeshPtr& b0, const MeshPtr& reference = nullptr,
                            const ParamMap& params = {}) {
  const auto& type = nodeType("geobrush.base_optimize");
  std::map<std::string, ValuePtr, std::less<>> inputs{{"base", b0}};
  if (reference) inputs["reference"] = reference;
  test::DirectContext ctx(type, inputs, params);
  type.create()->compute(ctx);
  NodeRun run;
  run.base = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["base"]);
  run.report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
  run.warnings = ctx.warnings;
  EXPECT_TRUE(run.base && run.report);
  return run;
}

class RealBase
    : public ::testing::TestWithParam<std::tuple<std::string, double, double, double, double>> {};

// A non-planar B0 over a canvas of a shared mesh: B stays a disc on B0's loop, faces turned as
// B0's, denser, with its smallest angle raised; the same input gives the same bits.
TEST_P(RealBase, StaysADiscTurnedLikeB0WithBetterAngles) {
  const auto& [file, x, y, z, radius] = GetParam();
  const MeshPtr b0 = realBase(file, Vector3d(x, y, z), radius);
  ASSERT_TRUE(b0);
  const NodeRun run = optimizeThroughNode(b0);
  const auto& v = run.report->values;
  expectBaseConvention(b0->surface, run.base->surface, v.at("target_length"));
  EXPECT_DOUBLE_EQ(v.at("reference_length"), minimumEdgeLength(b0->surface));
  EXPECT_EQ(v.at("vertices"), double(run.base->surface.n_vertices()));
  EXPECT_GT(run.base->surface.n_vertices(), 2 * b0->surface.n_vertices());
  EXPECT_EQ(facesFlippedAgainst(b0->surface, run.base->surface), 0);
  EXPECT_GT(v.at("min_angle_after_deg"), v.at("min_angle_before_deg"));
  EXPECT_DOUBLE_EQ(v.at("min_angle_after_deg"), minimumAngleDeg(run.base->surface));
  EXPECT_EQ(v.at("needles_left"), double(countNeedles(run.base->surface, 0.1)));
  EXPECT_EQ(run.warnings.empty(), v.at("needles_left") == 0);
  {
    std::ostringstream measured;
    measured << file << ": loop " << v.at("loop_vertices") << ", " << v.at("vertices")
             << " vertices, splits " << v.at("splits") << " (resplits " << v.at("resplits")
             << "), slices " << v.at("slices") << ", collapses " << v.at("collapses")
             << ", needles left " << v.at("needles_left") << ", min angle "
             << v.at("min_angle_before_deg") << " -> " << v.at("min_angle_after_deg") << " deg";
    RecordProperty("measured", measured.str());
  }
  const NodeRun again = optimizeThroughNode(b0);
  EXPECT_TRUE(test::bitIdentical(run.base->surface, again.base->surface));
}

INSTANTIATE_TEST_SUITE_P(Meshes, RealBase,
                         ::testing::Values(std::make_tuple("sphere.obj", 0.3, 0.5, 0.81, 0.7),
                                           std::make_tuple("bunny_small.obj", 0.0, 5.0, 3.5, 2.5)));

double loopLength(const TriMesh& mesh) {
  double length = 0;
  for (auto h : mesh.halfedges())
    if (mesh.is_boundary(h)) length += mesh.calc_edge_length(h);
  return length;
}

// A target base is sized by the source base: the reference's mean edge length scaled by the ratio
// of the loops' lengths (the paste's scale), not l_min.
TEST(BaseOptimizeNode, AReferenceMeshSetsTheDensity) {
  const MeshPtr source = realBase("sphere.obj", Vector3d(0.3, 0.5, 0.81), 0.7);
  const NodeRun sourceRun = optimizeThroughNode(source);
  const MeshPtr target = realBase("sphere.obj", Vector3d(-0.6, 0.2, -0.7), 0.9);
  const NodeRun run = optimizeThroughNode(target, sourceRun.base, {{"epsilon", 1.5}});
  const double mean = meanEdgeLength(sourceRun.base->surface) *
                      (loopLength(target->surface) / loopLength(sourceRun.base->surface));
  EXPECT_DOUBLE_EQ(run.report->values.at("reference_length"), mean);
  EXPECT_DOUBLE_EQ(run.report->values.at("target_length"), 1.5 * mean);
  expectBaseConvention(target->surface, run.base->surface, 1.5 * mean);
  EXPECT_EQ(facesFlippedAgainst(target->surface, run.base->surface), 0);
}

TEST(BaseOptimizeNode, NamesTheInputOrParamThatCannotWork) {
  auto expectRefusal = [](const MeshPtr& base, const MeshPtr& reference, const std::string& where,
                          const std::string& part) {
    try {
      optimizeThroughNode(base, reference);
      ADD_FAILURE() << "accepted a base that should fail with " << part;
    } catch (const NodeError& e) {
      EXPECT_EQ(e.where(), where);
      EXPECT_TRUE(test::contains(e.what(), part));
    }
  };
  const std::vector<Vector3d> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  TriMesh reversed;
  for (const auto& p : square)
    reversed.add_vertex(toPoint(p));
  reversed.add_face(TriMesh::VertexHandle(0), TriMesh::VertexHandle(1), TriMesh::VertexHandle(2));
  reversed.add_face(TriMesh::VertexHandle(0), TriMesh::VertexHandle(2), TriMesh::VertexHandle(3));
  expectRefusal(std::make_shared<const Mesh>(reversed), nullptr, "input 'base'",
                "does not run from vertex 0 to vertex 1");

  // A corner cut by 1e-4: l_min = 1e-4, and edges below 2e-4 over the unit square would need
  // some 3 x 10^7 vertices.
  const auto tinyEdge = std::make_shared<const Mesh>(
      fanBase({{0, 0, 0}, {1e-4, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  expectRefusal(tinyEdge, nullptr, "param 'epsilon'", "more than the limit of 2000000");
  // A reference whose edges are mostly near 1e-6 for a loop as long as the square's asks the same
  // of the unit square: a unit square beside a grid of 1e-6 squares.
  TriMesh tiny = fanBase(square);
  const int n = 200;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      tiny.add_vertex(TriMesh::Point(2 + 1e-6 * i, 1e-6 * j, 0));
  const auto grid = [&](int i, int j) { return TriMesh::VertexHandle(4 + j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tiny.add_face(grid(i, j), grid(i + 1, j), grid(i + 1, j + 1));
      tiny.add_face(grid(i, j), grid(i + 1, j + 1), grid(i, j + 1));
    }
  const auto tinyReference = std::make_shared<const Mesh>(tiny);
  expectRefusal(std::make_shared<const Mesh>(fanBase(square)), tinyReference, "input 'reference'",
                "more than the limit of 2000000");
  expectRefusal(std::make_shared<const Mesh>(fanBase(square)), std::make_shared<const Mesh>(),
                "input 'reference'", "not a positive length");
}

}  // namespace
}  // namespace geobrush
