#include "rbf_warp.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/border_loop.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

// The grid vertices on the square with corners (lo, lo) and (hi, hi), counter-clockwise.
std::vector<int> squareLoop(int n, int lo, int hi) {
  std::vector<int> loop;
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int i = lo; i < hi; ++i)
    loop.push_back(id(i, lo));
  for (int j = lo; j < hi; ++j)
    loop.push_back(id(hi, j));
  for (int i = hi; i > lo; --i)
    loop.push_back(id(i, hi));
  for (int j = hi; j > lo; --j)
    loop.push_back(id(lo, j));
  return loop;
}

// Pairs t_b_i = loop[i] with b_i = t_b_i + offset(t_b_i).
template <typename Offset>
PointPairs pairsOn(const TriMesh& mesh, const std::vector<int>& loop, const Offset& offset) {
  PointPairs pairs;
  for (int v : loop) {
    pairs.templateVertex.push_back(v);
    pairs.border.push_back(pointOf(mesh, v) + offset(pointOf(mesh, v)));
  }
  return pairs;
}

PointPairs raised(const TriMesh& mesh, const std::vector<int>& loop, double h) {
  return pairsOn(mesh, loop, [h](const Vector3d&) { return Vector3d(0, 0, h); });
}

RbfWarpResult warp(const TriMesh& mesh, const PointPairs& pairs, RbfWarpOptions options = {}) {
  const KnnGraph graph(vertexPoints(mesh), options.k);
  return rbfWarp(mesh, graph, pairs, options);
}

bool inside(const Vector3d& p, double lo, double hi) {
  const double e = 1e-12;
  return p.x() >= lo - e && p.x() <= hi + e && p.y() >= lo - e && p.y() <= hi + e;
}

// U3: the constraints t_b_i land on b_i; the raised plane reaches h along the loop and moves only
// along z (each D_i is a multiple of (0, 0, h)); the interior's deviation from h is recorded.
TEST(RbfWarp, RaisedSquareLoopReachesItsHeight) {
  const int n = 24;
  const TriMesh plane = test::unitSquareGrid(n);
  const auto loop = squareLoop(n, 6, 18);
  const double h = 0.1;
  RbfWarpOptions options;
  options.crop = false;
  const RbfWarpResult result = warp(plane, raised(plane, loop, h), options);
  RecordProperty("condition_number", std::to_string(result.conditionNumber));
  EXPECT_LT(result.maxResidual, 1e-8);
  EXPECT_EQ(result.constraintPair.size(), loop.size());
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (auto v : result.mesh.vertices()) {
    const Vector3d d = result.displacement[std::size_t(v.idx())];
    ASSERT_EQ(d.x(), 0.0) << v.idx();
    ASSERT_EQ(d.y(), 0.0) << v.idx();
    if (inside(pointOf(plane, v), 0.25, 0.75)) {
      low = std::min(low, d.z());
      high = std::max(high, d.z());
    }
  }
  for (int v : loop)
    EXPECT_NEAR(pointOf(result.mesh, v).z(), h, 1e-8 * h) << v;
  RecordProperty("interior_height_range",
                 std::to_string(low / h) + " .. " + std::to_string(high / h) + " h");
  // Without a polynomial term the constant h is not reproduced between the constraints: inside
  // the loop the plane bulges above h (by 5.3% of h here), never below it.
  EXPECT_GT(low, h * (1 - 1e-8));
  EXPECT_GT(high, 1.01 * h);
  EXPECT_LT(high, 1.1 * h);
}

// The crop keeps exactly the faces inside the loop, and its boundary is the loop itself.
TEST(RbfWarp, CropKeepsExactlyTheInsideOfASquareLoop) {
  const int n = 24, lo = 6, hi = 18;
  const TriMesh plane = test::unitSquareGrid(n);
  const auto loop = squareLoop(n, lo, hi);
  const RbfWarpResult result = warp(plane, raised(plane, loop, 0.05));
  EXPECT_EQ(result.mesh.n_faces(), std::size_t(2 * (hi - lo) * (hi - lo)));
  EXPECT_EQ(result.mesh.n_vertices(), std::size_t((hi - lo + 1) * (hi - lo + 1)));
  for (int v : result.sourceVertex)
    EXPECT_TRUE(inside(pointOf(plane, v), double(lo) / n, double(hi) / n)) << v;
  const auto loops = boundaryLoops(result.mesh);
  ASSERT_EQ(loops.size(), 1u);
  std::vector<int> boundary;
  for (int v : loops.front())
    boundary.push_back(result.sourceVertex[std::size_t(v)]);
  std::vector<int> expected = loop;
  std::sort(boundary.begin(), boundary.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(boundary, expected);
  EXPECT_EQ(result.constraintsKept, int(loop.size()));
}

// Pairs clockwise or counter-clockwise, the crop keeps the side holding the border's centroid.
TEST(RbfWarp, CropDoesNotDependOnTheLoopsDirection) {
  const int n = 20;
  const TriMesh plane = test::unitSquareGrid(n);
  auto loop = squareLoop(n, 4, 12);
  const RbfWarpResult forward = warp(plane, raised(plane, loop, 0.05));
  std::reverse(loop.begin(), loop.end());
  const RbfWarpResult backward = warp(plane, raised(plane, loop, 0.05));
  EXPECT_EQ(forward.sourceVertex, backward.sourceVertex);
  EXPECT_EQ(forward.mesh.n_faces(), std::size_t(2 * 8 * 8));
}

// stride s constrains pairs 0, s, 2s, ...: they land exactly, the pairs between only nearly.
// Pairs on every other vertex of a square loop, their border points lifted by a wave: the
// cropped boundary L is laid on the border polyline (corners on the b_i, the vertices between on
// the segments), with straight distances and a kernel the border's size.
TEST(RbfWarp, TheCroppedBoundaryIsLaidOnTheBorderPolyline) {
  const int n = 20;
  const TriMesh mesh = test::unitSquareGrid(n);
  std::vector<int> corners;
  const std::vector<int> loop = squareLoop(n, 4, 16);
  for (std::size_t i = 0; i < loop.size(); i += 2)
    corners.push_back(loop[i]);
  const PointPairs pairs = pairsOn(mesh, corners, [](const Vector3d& p) {
    return Vector3d(0, 0, 0.05 * std::sin(7 * p.x()) * std::cos(5 * p.y()));
  });
  RbfWarpOptions options;
  options.straightDistance = true;
  options.tMaxFromBorder = true;
  const RbfWarpResult result = warp(mesh, pairs, options);
  // The border's radius: between the square's half side and its half diagonal.
  EXPECT_GT(result.tMax, 0.3);
  EXPECT_LT(result.tMax, 0.3 * std::sqrt(2.0));
  EXPECT_LT(result.maxResidual, 1e-8);
  const auto loops = boundaryLoops(result.mesh);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), loop.size());
  for (int v : loops[0]) {
    const Vector3d p = pointOf(result.mesh, v);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < pairs.border.size(); ++i) {
      const Vector3d a = pairs.border[i], b = pairs.border[(i + 1) % pairs.border.size()];
      const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (a + s * (b - a) - p).norm());
    }
    EXPECT_LT(nearest, 1e-12) << v;
  }
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const auto at =
        std::lower_bound(result.sourceVertex.begin(), result.sourceVertex.end(), corners[i]);
    ASSERT_NE(at, result.sourceVertex.end());
    EXPECT_EQ(pointOf(result.mesh, int(at - result.sourceVertex.begin())), pairs.border[i]);
  }
}

// Distance from p to the closed polyline through `points`.
double toPolyline(const Vector3d& p, const std::vector<Vector3d>& points) {
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vector3d a = points[i], b = points[(i + 1) % points.size()];
    const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    nearest = std::min(nearest, (a + s * (b - a) - p).norm());
  }
  return nearest;
}

RbfWarpOptions snapping() {
  RbfWarpOptions options;
  options.straightDistance = true;
  options.tMaxFromBorder = true;
  return options;
}

// Border points paired with the template vertex of the pair before them (a border finer than the
// template there) each still get a boundary vertex of their own, so that the weld shares them all;
// here those points sit off the straight path, inside the square.
TEST(RbfWarp, EveryBorderPointGetsABoundaryVertex) {
  const int n = 24;
  const TriMesh mesh = test::unitSquareGrid(n);
  const std::vector<int> loop = squareLoop(n, 4, 20);
  PointPairs pairs;
  const Vector3d centre(0.5, 0.5, 0);
  for (std::size_t i = 0; i < loop.size(); i += 3) {
    const Vector3d corner = pointOf(mesh, loop[i]);
    pairs.templateVertex.push_back(loop[i]);
    pairs.border.push_back(corner + Vector3d(0, 0, 0.02 * std::sin(9 * corner.x())));
    if (i % 6 != 0) continue;
    // A point a third of the way to the next boundary vertex, pulled a little inside.
    const Vector3d next = pointOf(mesh, loop[(i + 1) % loop.size()]);
    pairs.templateVertex.push_back(loop[i]);
    pairs.border.push_back(corner + (next - corner) / 3 + 0.01 * (centre - corner).normalized());
  }
  const RbfWarpResult result = warp(mesh, pairs, snapping());
  const auto loops = boundaryLoops(result.mesh);
  ASSERT_EQ(loops.size(), 1u);
  for (const Vector3d& b : pairs.border) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int v : loops[0])
      nearest = std::min(nearest, (pointOf(result.mesh, v) - b).norm());
    EXPECT_LT(nearest, 1e-12) << b.transpose();
  }
  for (int v : loops[0])
    EXPECT_LT(toPolyline(pointOf(result.mesh, v), pairs.border), 1e-12) << v;
}

// Pairs on every other vertex of a square loop, starting at its second: the square's two corners
// with one face inside lie between pairs, and snapped onto the straight border between their
// neighbours they would make that face flat. Those faces are left out; no face is flat.
TEST(RbfWarp, TheSnapLeavesOutEarsItWouldFlatten) {
  const int n = 20;
  const TriMesh mesh = test::unitSquareGrid(n);
  const std::vector<int> loop = squareLoop(n, 4, 16);
  std::vector<int> corners;
  for (std::size_t i = 1; i < loop.size(); i += 2)
    corners.push_back(loop[i]);
  const PointPairs pairs = pairsOn(mesh, corners, [](const Vector3d& p) {
    return Vector3d(0, 0, 0.05 * std::sin(7 * p.x()) * std::cos(5 * p.y()));
  });
  const RbfWarpResult result = warp(mesh, pairs, snapping());
  // The grid vertices (16, 4) and (4, 16).
  for (int v : {4 * (n + 1) + 16, 16 * (n + 1) + 4})
    EXPECT_FALSE(std::binary_search(result.sourceVertex.begin(), result.sourceVertex.end(), v));
  const auto loops = boundaryLoops(result.mesh);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), loop.size() - 2);
  for (int v : loops[0])
    EXPECT_LT(toPolyline(pointOf(result.mesh, v), pairs.border), 1e-12) << v;
  const double spacing = 1.0 / n;
  for (const auto f : result.mesh.faces()) {
    const auto t = faceTriangle(result.mesh, f.idx());
    EXPECT_GT((t[1] - t[0]).cross(t[2] - t[0]).norm(), 0.1 * spacing * spacing) << f.idx();
  }
}

TEST(RbfWarp, StrideThinsTheConstraints) {
  const int n = 24;
  const TriMesh plane = test::unitSquareGrid(n);
  const auto loop = squareLoop(n, 6, 18);
  const auto pairs = pairsOn(plane, loop, [](const Vector3d& p) {
    return Vector3d(0.02 * std::sin(6 * p.y()), 0.01, 0.05 * std::cos(5 * p.x()));
  });
  RbfWarpOptions options;
  options.stride = 3;
  const RbfWarpResult result = warp(plane, pairs, options);
  ASSERT_EQ(result.constraintPair.size(), (loop.size() + 2) / 3);
  for (std::size_t i = 0; i < result.constraintPair.size(); ++i)
    EXPECT_EQ(result.constraintPair[i], int(3 * i));
  EXPECT_LT(result.maxResidual, 1e-8);
  EXPECT_GT(result.maxResidualAllPairs, 1e-6);
  EXPECT_LT(result.maxResidualAllPairs, 0.01);
  options.stride = 1;
  const RbfWarpResult dense = warp(plane, pairs, options);
  EXPECT_LT(dense.maxResidualAllPairs, 1e-8);
  RecordProperty("condition_stride_1", std::to_string(dense.conditionNumber));
  RecordProperty("condition_stride_3", std::to_string(result.conditionNumber));
  EXPECT_LT(result.conditionNumber, dense.conditionNumber);
}

// Two pairs on one template vertex cannot both hold: the later one is dropped and counted.
TEST(RbfWarp, PairsSharingATemplateVertexConstrainOnce) {
  const int n = 16;
  const TriMesh plane = test::unitSquareGrid(n);
  auto loop = squareLoop(n, 4, 12);
  loop.insert(loop.begin() + 5, loop[4]);
  const RbfWarpResult result = warp(plane, raised(plane, loop, 0.05));
  EXPECT_EQ(result.duplicatesDropped, 1);
  EXPECT_EQ(result.constraintPair.size(), loop.size() - 1);
  EXPECT_LT(result.maxResidualAllPairs, 1e-8);  // both ask the same here
}

std::shared_ptr<const PointPairs> shared(PointPairs pairs) {
  return std::make_shared<const PointPairs>(std::move(pairs));
}

test::NodeRun runWarp(const TriMesh& mesh, const PointPairs& pairs, const ParamMap& params = {}) {
  return test::runNode("geobrush.rbf_warp",
                       {{"template", std::make_shared<const Mesh>(mesh)}, {"pairs", shared(pairs)}},
                       params);
}

TEST(RbfWarpNode, ReportsAndRepeatsBitForBit) {
  const int n = 20;
  const TriMesh plane = test::unitSquareGrid(n);
  const auto pairs = raised(plane, squareLoop(n, 5, 15), 0.1);
  const auto first = runWarp(plane, pairs);
  const auto second = runWarp(plane, pairs);
  const auto mesh = first.get<Mesh>("template");
  const auto report = first.get<Metrics>("report");
  ASSERT_TRUE(mesh && report && second.get<Mesh>("template"));
  EXPECT_EQ(mesh->contentHash(), second.get<Mesh>("template")->contentHash());
  EXPECT_EQ(report->values.at("constraints"), 40.0);
  EXPECT_EQ(report->values.at("kept_vertices"), 121.0);
  EXPECT_EQ(report->values.at("kept_faces"), 200.0);
  EXPECT_LT(report->values.at("max_residual_relative"), 1e-8);
  EXPECT_GT(report->values.at("condition_number"), 1.0);
  EXPECT_EQ(report->values.at("t_max"), std::sqrt(2.0));
  EXPECT_TRUE(first.warnings.empty());
}

// The template's kNN graph is derived data: new pairs or a new t_max reuse it, a new k does not.
TEST(RbfWarpNode, BuildsTheTemplatesGraphOncePerK) {
  const int n = 16;
  const TriMesh plane = test::unitSquareGrid(n);
  const auto mesh = std::make_shared<const Mesh>(plane);
  const NodeType* type = test::registry().find("geobrush.rbf_warp");
  ASSERT_TRUE(type);
  auto derived = std::make_shared<DerivedStore>();
  auto compute = [&](double h, const ParamMap& params) {
    test::DirectContext ctx(
        *type, {{"template", mesh}, {"pairs", shared(raised(plane, squareLoop(n, 4, 12), h))}},
        params, derived);
    type->create()->compute(ctx);
    return std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
  };
  compute(0.1, {});
  compute(0.2, {{"t_max", 0.5}});
  EXPECT_EQ(derived->builds(), 1u);
  const auto report = compute(0.2, {{"k", std::int64_t(6)}});
  ASSERT_TRUE(report);
  EXPECT_LT(report->values.at("max_residual_relative"), 1e-8);
  EXPECT_EQ(derived->builds(), 2u);
}

// Each bad input: one NodeError naming the port.
void expectRefused(const TriMesh& mesh, const PointPairs& pairs, const std::string& port,
                   const std::string& part, const ParamMap& params = {}) {
  try {
    runWarp(mesh, pairs, params);
    ADD_FAILURE() << "accepted: " << part;
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input '" + port + "'");
    EXPECT_TRUE(test::contains(e.what(), part));
  }
}

TEST(RbfWarpNode, RefusesBadInputNamingThePort) {
  const int n = 12;
  const TriMesh plane = test::unitSquareGrid(n);
  const auto loop = squareLoop(n, 3, 9);
  const PointPairs good = raised(plane, loop, 0.1);

  PointPairs mismatched = good;
  mismatched.border.pop_back();
  expectRefused(plane, mismatched, "pairs", "border points but");
  PointPairs outOfRange = good;
  outOfRange.templateVertex[2] = 1000;
  expectRefused(plane, outOfRange, "pairs", "lacks");
  PointPairs notFinite = good;
  notFinite.border[1].x() = std::numeric_limits<double>::quiet_NaN();
  expectRefused(plane, notFinite, "pairs", "not finite");
  expectRefused(plane, raised(plane, {loop[0], loop[3]}, 0.1), "pairs", "at least 3");
  expectRefused(plane, good, "pairs", "at least 3", {{"stride", std::int64_t(12)}});
  // Three vertices in a row: L runs there and back and encloses nothing.
  expectRefused(plane, raised(plane, {loop[0], loop[2], loop[4]}, 0.1), "pairs",
                "does not separate");
  TriMesh noFaces;
  for (int i = 0; i < 4; ++i)
    noFaces.add_vertex(TriMesh::Point(i, i * i, 0));
  expectRefused(noFaces, raised(noFaces, {0, 1, 2}, 0.1), "template", "no faces");
}

// A real case: the patch cut from the bunny's back, displaced, is warped back onto the hole's
// border; its boundary vertices then coincide with the border's. Its boundary is L, so the crop
// keeps it whole.
TEST(RbfWarpNode, WarpsTheBunnyPatchOntoItsHolesBorder) {
  const auto patch = readMesh(test::meshPath("cases/bunny_small_back_removed_patch.obj")).mesh;
  const auto hole = readMesh(test::meshPath("cases/bunny_small_back_hole.obj")).mesh;
  const auto holeLoops = boundaryLoops(hole->surface);
  const auto patchLoops = boundaryLoops(patch->surface);
  ASSERT_EQ(holeLoops.size(), 1u);
  ASSERT_EQ(patchLoops.size(), 1u);
  TriMesh moved = patch->surface;
  const double diagonal = boundingDiagonal(moved);
  for (auto v : moved.vertices()) {
    const Vector3d p = pointOf(moved, v);
    const Vector3d shift(std::sin(p.y()), std::cos(p.z()), std::sin(p.x() + p.z()));
    moved.set_point(v, toPoint(p + 0.03 * diagonal * shift));
  }
  PointPairs pairs;
  for (int b : holeLoops.front()) {
    const Vector3d point = pointOf(hole->surface, b);
    int nearest = -1;
    for (int t : patchLoops.front())
      if (nearest < 0 ||
          (pointOf(moved, t) - point).norm() < (pointOf(moved, nearest) - point).norm())
        nearest = t;
    pairs.border.push_back(point);
    pairs.templateVertex.push_back(nearest);
  }
  const auto run = runWarp(moved, pairs);
  const auto warped = run.get<Mesh>("template");
  const auto report = run.get<Metrics>("report");
  ASSERT_TRUE(warped && report);
  RecordProperty("condition_number", std::to_string(report->values.at("condition_number")));
  EXPECT_EQ(report->values.at("constraints") + report->values.at("duplicates_dropped"),
            double(holeLoops.front().size()));
  EXPECT_EQ(warped->surface.n_vertices(), patch->surface.n_vertices());
  EXPECT_LT(report->values.at("max_residual_all_pairs_relative"), 1e-8);
  const auto warpedLoops = boundaryLoops(warped->surface);
  ASSERT_EQ(warpedLoops.size(), 1u);
  for (int t : warpedLoops.front()) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int b : holeLoops.front())
      nearest = std::min(nearest, (pointOf(warped->surface, t) - pointOf(hole->surface, b)).norm());
    EXPECT_LT(nearest, 1e-8 * diagonal) << t;
  }
}

}  // namespace
}  // namespace geobrush
