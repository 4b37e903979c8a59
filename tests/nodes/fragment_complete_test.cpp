#include "fragment_complete.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/node.hpp"
#include "geobrush/point_neighbours.hpp"
#include "geobrush/region.hpp"
#include "geobrush/surface_point.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;
using Height = std::function<double(double, double)>;

// The square [0, n]^2 cut into n x n unit squares of two triangles each, lifted to z = height.
TriMesh heightGrid(int n, const Height& height) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.add_vertex(TriMesh::Point(i, j, height(i, j)));
  auto id = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return mesh;
}

// 0 for the vertices within `radius` of (cx, cy) in the xy plane (the hole), 1 elsewhere.
std::vector<std::uint8_t> outsideDisc(const TriMesh& mesh, double cx, double cy, double radius) {
  std::vector<std::uint8_t> original;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    original.push_back(std::hypot(p[0] - cx, p[1] - cy) <= radius ? 0 : 1);
  }
  return original;
}

// The membrane (harmonic) fill of the hole's heights from its rim: Gauss-Seidel on the uniform
// Laplacian until the sweeps stop changing anything.
void membraneFill(TriMesh& mesh, const std::vector<std::uint8_t>& original) {
  for (int sweep = 0; sweep < 5000; ++sweep)
    for (auto v : mesh.vertices()) {
      if (original[std::size_t(v.idx())]) continue;
      double sum = 0;
      int count = 0;
      for (auto w : mesh.vv_range(v))
        sum += mesh.point(w)[2], ++count;
      mesh.point(v)[2] = sum / count;
    }
}

PasteMap pasteMapOf(const std::vector<std::uint8_t>& original) {
  PasteMap map;
  for (std::size_t v = 0; v < original.size(); ++v)
    map.targetVertex.push_back(original[v] ? int(v) : -1);
  return map;
}

// The root mean square of height - z over the vertices not original.
double holeRms(const TriMesh& mesh, const std::vector<std::uint8_t>& original,
               const Height& height) {
  double sum = 0;
  int count = 0;
  for (auto v : mesh.vertices())
    if (!original[std::size_t(v.idx())]) {
      const auto& p = mesh.point(v);
      sum += std::pow(p[2] - height(p[0], p[1]), 2);
      ++count;
    }
  return std::sqrt(sum / count);
}

TEST(FragmentComplete, TheScaleSpaceKeepsAPlaneAndItsNormals) {
  const Height plane = [](double x, double y) { return 0.3 * x - 0.2 * y + 1; };
  const TriMesh mesh = heightGrid(12, plane);
  const auto space = scaleSpace(mesh, 2);
  ASSERT_EQ(space.size(), 3u);
  const Vector3d n = Vector3d(-0.3, 0.2, 1).normalized();
  for (const auto& level : space)
    for (const auto& p : level)
      EXPECT_NEAR(p.z(), plane(p.x(), p.y()), 1e-12);
  for (const auto& normal : areaWeightedNormals(mesh, space[2]))
    EXPECT_NEAR(normal.dot(n), 1.0, 1e-12);
}

TEST(FragmentComplete, TheRimInwardOrderGoesRingByRingThenByIndex) {
  const TriMesh mesh = heightGrid(10, [](double, double) { return 0.0; });
  const auto original = outsideDisc(mesh, 5, 5, 3.2);
  const auto order = rimInwardOrder(mesh, original);
  std::vector<int> ring(mesh.n_vertices(), 0);
  int holes = 0;
  for (std::size_t v = 0; v < original.size(); ++v)
    holes += original[v] ? 0 : 1;
  ASSERT_EQ(order.size(), std::size_t(holes));
  for (std::size_t k = 0; k < order.size(); ++k) {
    int nearest = 1 << 20;
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(order[k])))
      if (original[std::size_t(w.idx())] || ring[std::size_t(w.idx())] > 0)
        nearest = std::min(nearest, ring[std::size_t(w.idx())]);
    ring[std::size_t(order[k])] = nearest + 1;
    if (k > 0) {
      const int a = ring[std::size_t(order[k - 1])], b = ring[std::size_t(order[k])];
      EXPECT_TRUE(a < b || (a == b && order[k - 1] < order[k])) << k;
    }
  }
  EXPECT_GE(ring[std::size_t(5 * 11 + 5)], 3);  // the centre is three rings in
}

// U6: every completed vertex of a planar hole in a plane stays on the plane.
TEST(FragmentComplete, APlanarHoleStaysPlanar) {
  const Height plane = [](double x, double y) { return 0.25 * x + 0.1 * y - 2; };
  const TriMesh mesh = heightGrid(30, plane);
  const auto original = outsideDisc(mesh, 14.6, 15.3, 5);
  const auto result = fragmentComplete(mesh, original, {});
  EXPECT_GT(result.completed, 50u);
  EXPECT_GT(result.candidates, 100u);
  const Vector3d n = Vector3d(-0.25, -0.1, 1).normalized();
  for (auto v : result.mesh.vertices()) {
    const Vector3d p = pointOf(result.mesh, v);
    EXPECT_NEAR((p - Vector3d(0, 0, -2)).dot(n), 0.0, 1e-10) << v.idx();
  }
  EXPECT_LT(result.meanBestCost, 1e-20);
}

// The periodic relief z = a sin(2 pi x / lambda) sin(2 pi y / lambda), lambda 8 edges.
const double kAmplitude = 0.5;
const double kPeriod = 8;
double relief(double x, double y) {
  const double k = 2 * std::numbers::pi / kPeriod;
  return kAmplitude * std::sin(k * x) * std::sin(k * y);
}

struct ReliefCase {
  TriMesh filled;
  std::vector<std::uint8_t> original;
};

// A 6 x 6 period relief with a hole 1.5 periods across, closed by the membrane fill.
ReliefCase reliefCase() {
  ReliefCase c{heightGrid(48, relief), {}};
  c.original = outsideDisc(c.filled, 23.3, 24.6, 0.75 * kPeriod);
  membraneFill(c.filled, c.original);
  return c;
}

// U6: detail copied from the rest of the relief brings the hole close to the true relief.
TEST(FragmentComplete, APeriodicReliefIsRestoredWellBelowTheMembraneFillsError) {
  const ReliefCase c = reliefCase();
  const auto result = fragmentComplete(c.filled, c.original, {});
  const double membrane = holeRms(c.filled, c.original, relief);
  const double completed = holeRms(result.mesh, c.original, relief);
  std::printf(
      "relief hole RMS: membrane fill %.4g, completed %.4g (%zu vertices, %zu candidates)\n",
      membrane, completed, result.completed, result.candidates);
  RecordProperty("membrane_rms", std::to_string(membrane));
  RecordProperty("completed_rms", std::to_string(completed));
  EXPECT_GT(membrane, 0.2 * kAmplitude);
  EXPECT_LT(completed, 0.5 * membrane);
  // The coarsest base stays the guidance's (section 6), so what the true relief keeps at that
  // scale bounds the error from below; the copied detail levels add little to it.
  const auto truth = scaleSpace(heightGrid(48, relief), 2);
  const auto guidance = scaleSpace(c.filled, 2);
  double sum = 0;
  int count = 0;
  for (std::size_t v = 0; v < c.original.size(); ++v)
    if (!c.original[v]) sum += std::pow(truth[2][v].z() - guidance[2][v].z(), 2), ++count;
  const double coarsest = std::sqrt(sum / count);
  std::printf("coarsest base RMS difference %.4g\n", coarsest);
  EXPECT_LT(completed, 1.2 * coarsest);
}

// U7: original vertices have confidence 1, completed ones less, falling with the cost.
TEST(FragmentComplete, OriginalVerticesAreConfidentAndCompletedOnesLess) {
  const ReliefCase c = reliefCase();
  const auto result = fragmentComplete(c.filled, c.original, {});
  ASSERT_EQ(result.confidence.size(), c.filled.n_vertices());
  for (std::size_t v = 0; v < c.original.size(); ++v) {
    if (c.original[v]) {
      EXPECT_EQ(result.confidence[v], 1.0);
      EXPECT_EQ(result.mesh.point(TriMesh::VertexHandle(int(v))),
                c.filled.point(TriMesh::VertexHandle(int(v))));
    } else {
      EXPECT_GE(result.confidence[v], 0.0);
      EXPECT_LE(result.confidence[v], kCompletedConfidence);
    }
  }
  EXPECT_EQ(completedConfidence(0, 1), kCompletedConfidence);
  EXPECT_LT(completedConfidence(0.25, 1), completedConfidence(0.01, 1));
  EXPECT_EQ(completedConfidence(std::numeric_limits<double>::infinity(), 1), 0.0);
}

TEST(FragmentComplete, TwoRunsAndAnyThreadCountAreBitIdentical) {
  const ReliefCase c = reliefCase();
  FragmentCompleteOptions one;
  one.threads = 1;
  const auto a = fragmentComplete(c.filled, c.original, {});
  const auto serial = fragmentComplete(c.filled, c.original, one);
  EXPECT_TRUE(test::bitIdentical(a.mesh, serial.mesh));
  EXPECT_EQ(a.confidence, serial.confidence);
  EXPECT_EQ(a.meanBestCost, serial.meanBestCost);
}

// Runs the registered node on a mesh and paste map.
test::NodeRun runNode(const TriMesh& mesh, const PasteMap& map, const ParamMap& params = {}) {
  return test::runNode("geobrush.fragment_complete",
                       {{"mesh", std::make_shared<const Mesh>(mesh)},
                        {"paste_map", std::make_shared<const PasteMap>(map)}},
                       params);
}

TEST(FragmentCompleteNode, OutputsTheMeshConfidenceAndReport) {
  const ReliefCase c = reliefCase();
  const auto run = runNode(c.filled, pasteMapOf(c.original));
  const auto mesh = run.get<Mesh>("mesh");
  const auto fields = run.get<VertexFields>("confidence");
  const auto report = run.get<Metrics>("report");
  ASSERT_TRUE(mesh && fields && report);
  EXPECT_EQ(fields->mismatch(mesh->surface), "");
  EXPECT_EQ(fields->names(), std::vector<std::string>{"confidence"});
  EXPECT_EQ(report->values.at("completed"),
            double(std::count(c.original.begin(), c.original.end(), 0)));
  EXPECT_GT(report->values.at("candidates"), 0);
  EXPECT_GE(report->values.at("mean_best_cost"), 0);
  EXPECT_EQ(test::faceIndices(mesh->surface), test::faceIndices(c.filled));
}

// The NodeError a run throws; fails when it throws none.
NodeError nodeError(const TriMesh& mesh, const PasteMap& map, const ParamMap& params = {}) {
  try {
    runNode(mesh, map, params);
  } catch (const NodeError& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return NodeError("none");
}

TEST(FragmentCompleteNode, BadInputsNameTheirPortOrParam) {
  const ReliefCase c = reliefCase();
  const PasteMap map = pasteMapOf(c.original);
  PasteMap shorter = map;
  shorter.targetVertex.pop_back();
  EXPECT_EQ(nodeError(c.filled, shorter).where(), "input 'paste_map'");
  PasteMap none = map;
  std::fill(none.targetVertex.begin(), none.targetVertex.end(), -1);
  EXPECT_EQ(nodeError(c.filled, none).where(), "input 'paste_map'");
  EXPECT_EQ(nodeError(TriMesh(), PasteMap()).where(), "input 'mesh'");
  TriMesh broken = c.filled;
  broken.point(TriMesh::VertexHandle(3))[1] = std::nan("");
  EXPECT_EQ(nodeError(broken, map).where(), "input 'mesh'");
  EXPECT_EQ(nodeError(c.filled, map, {{"radius", 100.0}}).where(), "param 'radius'");
  EXPECT_EQ(nodeError(c.filled, map, {{"levels", std::int64_t(0)}}).where(), "param 'levels'");
  EXPECT_EQ(nodeError(c.filled, map, {{"desc_res", std::int64_t(1)}}).where(), "param 'desc_res'");
  EXPECT_EQ(nodeError(c.filled, map, {{"rotations", std::int64_t(0)}}).where(),
            "param 'rotations'");
  EXPECT_EQ(nodeError(c.filled, map, {{"guidance_weight", -1.0}}).where(),
            "param 'guidance_weight'");
  EXPECT_EQ(nodeError(c.filled, map, {{"candidate_stride", std::int64_t(0)}}).where(),
            "param 'candidate_stride'");
  // 6 levels x 113 completed x 2,200 candidates x 360 rotations x 5,120 cells: refused at once.
  const NodeError tooMuch = nodeError(c.filled, map,
                                      {{"levels", std::int64_t(6)},
                                       {"rotations", std::int64_t(360)},
                                       {"desc_res", std::int64_t(64)}});
  EXPECT_EQ(tooMuch.where(), "param 'candidate_stride'");
  EXPECT_TRUE(test::contains(tooMuch.what(), "limit"));
}

// The distance from p to the surface of `mesh`, over the faces around its 8 vertices nearest p.
double distanceTo(const TriMesh& mesh, const PointNeighbours& vertices, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (int v : vertices.nearest(p, 8))
    for (auto f : mesh.vf_range(TriMesh::VertexHandle(v))) {
      std::vector<Vector3d> c;
      for (auto w : mesh.fv_range(f))
        c.push_back(pointOf(mesh, w));
      best = std::min(best, (closestPointOnTriangle(p, c[0], c[1], c[2]) - p).norm());
    }
  return best;
}

// The mean distance from the vertices not original to the removed surface.
double meanDistance(const TriMesh& mesh, const std::vector<std::uint8_t>& original,
                    const TriMesh& removed) {
  std::vector<Vector3d> points;
  for (auto v : removed.vertices())
    points.push_back(pointOf(removed, v));
  const PointNeighbours index(std::move(points));
  double sum = 0;
  int count = 0;
  for (auto v : mesh.vertices())
    if (!original[std::size_t(v.idx())])
      sum += distanceTo(removed, index, pointOf(mesh, v)), ++count;
  return sum / count;
}

// A real case: the forehead hole of nefertiti filled by the GeoBrush fill graph (membrane, G = 0,
// stitched), then completed from the rest of the head. The connectivity and the original vertices
// stay as they are; the distances to the removed surface, the fill's and the completion's, are
// printed.
TEST(FragmentCompleteNode, CompletesTheBunnyBackFill) {
  Graph graph = readGraphFile(test::sourceDir() / "graphs" / "fill_bunny_small_back.json");
  prepareGraph(graph, test::registry());
  EvalOptions options;
  options.outputDir = test::tempDir("fragment-complete-bunny");
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph, options);
  ASSERT_TRUE(report.ok) << report.error;
  const auto filled = std::dynamic_pointer_cast<const Mesh>(evaluator.output("stitch", "mesh"));
  const auto map = std::dynamic_pointer_cast<const PasteMap>(evaluator.output("stitch", "map"));
  ASSERT_TRUE(filled && map);
  const auto run = runNode(filled->surface, *map);
  const auto completed = run.get<Mesh>("mesh");
  const auto confidence = run.get<VertexFields>("confidence");
  ASSERT_TRUE(completed && confidence);
  const test::Topology before = test::topology(filled->surface);
  const test::Topology after = test::topology(completed->surface);
  EXPECT_EQ(after.boundaryLoops, before.boundaryLoops);
  EXPECT_EQ(after.nonManifoldVertices, before.nonManifoldVertices);
  EXPECT_EQ(after.eulerCharacteristic, before.eulerCharacteristic);
  EXPECT_EQ(test::faceIndices(completed->surface), test::faceIndices(filled->surface));
  std::vector<std::uint8_t> original;
  for (int t : map->targetVertex)
    original.push_back(t >= 0 ? 1 : 0);
  const auto& c = confidence->column("confidence");
  std::size_t moved = 0;
  for (auto v : filled->surface.vertices()) {
    const auto i = std::size_t(v.idx());
    if (original[i]) {
      EXPECT_EQ(completed->surface.point(v), filled->surface.point(v)) << i;
      EXPECT_EQ(c[i], 1.0);
    } else {
      EXPECT_TRUE(pointOf(completed->surface, v).allFinite());
      EXPECT_LT(c[i], 1.0);
      moved += completed->surface.point(v) != filled->surface.point(v) ? 1 : 0;
    }
  }
  EXPECT_GT(moved, 0u);
  // The patch reaches past the hole: the whole original bunny is the ground truth of every
  // completed vertex, the removed patch that of those over the hole.
  const MeshPtr removed = readMesh(test::meshPath("cases/bunny_small_back_removed_patch.obj")).mesh;
  const MeshPtr whole = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto metrics = run.get<Metrics>("report");
  std::printf("bunny back: %g completed, %g candidates, mean best cost %g, mean edge %.4g\n",
              metrics->values.at("completed"), metrics->values.at("candidates"),
              metrics->values.at("mean_best_cost"), meanEdgeLength(filled->surface));
  for (const auto& [name, truth] :
       {std::pair{"removed_patch", removed}, std::pair{"bunny", whole}}) {
    const double fill = meanDistance(filled->surface, original, truth->surface);
    const double done = meanDistance(completed->surface, original, truth->surface);
    std::printf("mean distance to the %s: fill %.4g, completed %.4g\n", name, fill, done);
    RecordProperty(std::string(name) + "_fill", std::to_string(fill));
    RecordProperty(std::string(name) + "_completed", std::to_string(done));
    EXPECT_TRUE(std::isfinite(done));
  }
}

}  // namespace
}  // namespace geobrush
