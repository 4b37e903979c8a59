#include "geobrush/exponential_map.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

double bump(double x, double y) {
  const double s = 1 - (x * x + y * y) / (0.6 * 0.6);
  return s > 0 ? 1.5 * s * s * s : 0.0;
}

using test::DirectContext;

TEST(GdemNode, OutputsTheGeneralizedMap) {
  const NodeType* type = test::registry().find("geobrush.gdem");
  ASSERT_NE(type, nullptr);
  const MeshPtr mesh = test::heightGrid(30, bump);
  const auto canvas = std::make_shared<const Canvas>(test::growDiscCanvas(mesh, 100, 10));
  DirectContext ctx(*type, {{"canvas", canvas}}, {{"angle", 20.0}});
  type->create()->compute(ctx);
  EXPECT_TRUE(ctx.warnings.empty());
  const auto out =
      std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["parameterization"]);
  ASSERT_NE(out, nullptr);
  DemOptions o;
  o.angleDegrees = 20;
  const DemResult dem = discreteExponentialMap(*canvas, o);
  EXPECT_EQ(out->canvas, canvas);
  EXPECT_EQ(out->uv, dem.uv);
  EXPECT_EQ(out->normal, dem.normal);
  EXPECT_EQ(out->reversedFaces, dem.reversedFaces);
  EXPECT_EQ(out->origin.vAxis, dem.origin.vAxis);
  EXPECT_EQ(out->rotation, 0.0);
  EXPECT_EQ(out->scale, 1.0);

  DirectContext bad(*type, {{"canvas", canvas}}, {{"neighbours", std::int64_t{0}}});
  try {
    type->create()->compute(bad);
    ADD_FAILURE() << "accepted 0 neighbours";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'neighbours'");
  }
}

TEST(GdemNode, RunsAfterCanvasGrowInAGraph) {
  Graph graph;
  graph.nodes["mesh"] = {
      "geobrush.load_mesh", 1, {{"path", test::meshPath("bunny_small.obj").string()}}};
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto p = bunny->surface.point(TriMesh::VertexHandle(1000));
  graph.nodes["canvas"] = {
      "geobrush.canvas_grow",
      1,
      {{"origin", Vec3{p[0], p[1], p[2]}}, {"dabs", std::vector<double>{p[0], p[1], p[2], 1.5}}}};
  graph.nodes["map"] = {"geobrush.gdem", 1, {}};
  graph.connections.push_back({{"mesh", "mesh"}, {"canvas", "mesh"}});
  graph.connections.push_back({{"canvas", "canvas"}, {"map", "canvas"}});
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  const auto map = std::dynamic_pointer_cast<const Parameterization>(
      evaluator.output("map", "parameterization"));
  ASSERT_NE(map, nullptr);
  ASSERT_EQ(map->uv.size(), map->canvas->surface.n_vertices());
  EXPECT_TRUE(test::boundaryIsSimple(*map->canvas, map->uv));
  EXPECT_EQ(map->reversedFaces.size(), map->canvas->surface.n_faces());
}

}  // namespace
}  // namespace geobrush
