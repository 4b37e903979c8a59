#include "emd_correspond.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "emd_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/recycle_bin.hpp"
#include "geobrush/vertex_fields.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

MeshPtr flatGrid(int n, double shift = 0.0) {
  return test::heightGrid(
      n, [](double, double) { return 0.0; },
      Eigen::Isometry3d(Eigen::Translation3d(shift, shift, 0)));
}

std::vector<double> linear(const TriMesh& mesh) {
  std::vector<double> values;
  for (auto v : mesh.vertices())
    values.push_back(2 * mesh.point(v)[0] - 3 * mesh.point(v)[1] + 0.5);
  return values;
}

const auto everywhere = [](const Vector2d&) { return true; };

// T4: the same canvas on both sides and k = 1: each vertex corresponds to itself.
TEST(EmdCorrespond, MapsACanvasOntoItselfVertexForVertex) {
  const MeshPtr grid = flatGrid(8);
  const auto param = test::projectedParameterization(grid, Vector3d::UnitX(), Vector3d::UnitY());
  const auto region = test::regionWhere(*param, *param, everywhere);
  const std::vector<double> h = linear(grid->surface);
  const EmdCorrespondence result =
      correspondInDomain(*param, *param, region->targetVertices, {&h}, {.neighbours = 1});
  for (std::size_t v = 0; v < h.size(); ++v) {
    EXPECT_EQ(result.nearest[v], int(v));
    EXPECT_EQ(result.sampled[0][v], h[v]);
  }
}

// Eq. 4's mean: a target vertex at the centre of a source cell has its four corners as nearest
// vertices, and the mean of a linear field over them is its value there.
TEST(EmdCorrespond, AveragesTheKNearestSourceVertices) {
  const int n = 8;
  const MeshPtr source = flatGrid(n), target = flatGrid(n, 1.0 / n);  // half a cell over
  const auto sourceParam =
      test::projectedParameterization(source, Vector3d::UnitX(), Vector3d::UnitY());
  const auto targetParam =
      test::projectedParameterization(target, Vector3d::UnitX(), Vector3d::UnitY());
  const auto region = test::regionWhere(
      *sourceParam, *targetParam, [](const Vector2d& u) { return u.cwiseAbs().maxCoeff() < 0.9; });
  ASSERT_FALSE(region->targetVertices.empty());
  const std::vector<double> h = linear(source->surface);
  const EmdCorrespondence result =
      correspondInDomain(*sourceParam, *targetParam, region->targetVertices, {&h}, {});
  const std::vector<double> expected = linear(target->surface);
  std::vector<std::uint8_t> inside(expected.size(), 0);
  for (int v : region->targetVertices)
    inside[std::size_t(v)] = 1;
  for (std::size_t v = 0; v < expected.size(); ++v) {
    if (inside[v]) {
      EXPECT_NEAR(result.sampled[0][v], expected[v], 1e-12) << v;
      EXPECT_GE(result.nearest[v], 0);
    } else {
      EXPECT_EQ(result.sampled[0][v], 0.0);
      EXPECT_EQ(result.nearest[v], -1);
    }
  }
}

TEST(EmdCorrespond, RefusesBadNeighbourCountsAndFields) {
  const MeshPtr grid = flatGrid(4);
  const auto param = test::projectedParameterization(grid, Vector3d::UnitX(), Vector3d::UnitY());
  const std::vector<double> h = linear(grid->surface), shortField(3);
  EXPECT_THROW(correspondInDomain(*param, *param, {0}, {&h}, {.neighbours = 0}), std::out_of_range);
  EXPECT_THROW(correspondInDomain(*param, *param, {0}, {&shortField}, {}), std::invalid_argument);
  EXPECT_THROW(correspondInDomain(*param, *param, {1000}, {&h}, {}), std::invalid_argument);
}

// The node on a real mesh onto itself: the modes come back on the region (k = 1), zero off it,
// with region and nearest beside them; the residue does not transfer.
TEST(EmdCorrespondNode, SamplesTheSourceModesOfARealMeshOnTheRegion) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto param = test::projectedParameterization(bunny, Vector3d::UnitX(), Vector3d::UnitY());
  const Vector2d centre = param->uv[0];
  const double radius = 0.1 * boundingDiagonal(bunny->surface);
  const auto region = test::regionWhere(
      *param, *param, [&](const Vector2d& u) { return (u - centre).norm() < radius; });
  auto modes = std::make_shared<VertexFields>(bunny->surface);
  modes->add("h1", linear(bunny->surface));
  modes->add("r", std::vector<double>(modes->vertexCount, 7.0));
  const test::NodeRun run = test::runNode(
      "geobrush.emd_correspond",
      {{"region", region}, {"source", param}, {"target", param}, {"source_modes", modes}},
      {{"neighbours", std::int64_t(1)}});
  const auto sampled = run.get<VertexFields>("sampled");
  ASSERT_TRUE(sampled);
  EXPECT_EQ(sampled->names(), (std::vector<std::string>{"h1", "region", "nearest"}));
  EXPECT_EQ(sampled->mismatch(bunny->surface), "");
  std::vector<std::uint8_t> inside(modes->vertexCount, 0);
  for (int v : region->targetVertices)
    inside[std::size_t(v)] = 1;
  ASSERT_GT(region->targetVertices.size(), 10u);
  for (std::size_t v = 0; v < inside.size(); ++v) {
    EXPECT_EQ(sampled->column("region")[v], inside[v] ? 1.0 : 0.0);
    // Distinct vertices of a scan may share a projection: the nearest then holds the same value.
    if (inside[v]) {
      EXPECT_EQ(sampled->column("h1")[v],
                modes->column("h1")[std::size_t(sampled->column("nearest")[v])]);
    } else {
      EXPECT_EQ(sampled->column("h1")[v], 0.0);
    }
  }
}

// A dab after a dab, on regions apart: the node re-samples into its retired output (one object
// throughout), cleared where the earlier region was, and gives what a fresh node gives.
TEST(EmdCorrespondNode, EditAfterEditGivesWhatAFreshNodeGives) {
  const NodeType* type = test::registry().find("geobrush.emd_correspond");
  ASSERT_NE(type, nullptr);
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto param = test::projectedParameterization(bunny, Vector3d::UnitX(), Vector3d::UnitY());
  const double radius = 0.1 * boundingDiagonal(bunny->surface);
  const auto far = std::size_t(test::farthestInDomain(*param, 0));
  ASSERT_GT((param->uv[far] - param->uv[0]).norm(), 2 * radius);
  auto modes = std::make_shared<VertexFields>(bunny->surface);
  modes->add("h1", linear(bunny->surface));
  modes->add("h2", std::vector<double>(modes->vertexCount, 0.25));
  const auto node = type->create();
  const auto bin = std::make_shared<RecycleBin>();
  std::set<const VertexFields*> made;
  for (int edit = 0; edit < 6; ++edit) {
    SCOPED_TRACE(edit);
    const Vector2d centre = param->uv[edit < 3 ? 0 : far];
    const double reach = radius * (1.0 + 0.2 * (edit % 3));
    const auto region = test::regionWhere(
        *param, *param, [&](const Vector2d& u) { return (u - centre).norm() < reach; });
    const std::map<std::string, ValuePtr, std::less<>> inputs = {
        {"region", region}, {"source", param}, {"target", param}, {"source_modes", modes}};
    test::DirectContext ctx(*type, inputs, {}, nullptr, bin);
    test::run(*node, ctx);
    const auto sampled = std::dynamic_pointer_cast<const VertexFields>(ctx.outputs.at("sampled"));
    ASSERT_NE(sampled, nullptr);
    made.insert(sampled.get());
    const auto fresh =
        test::runNode("geobrush.emd_correspond", inputs).get<VertexFields>("sampled");
    EXPECT_EQ(sampled->names(), fresh->names());
    EXPECT_EQ(sampled->meshHash, fresh->meshHash);
    EXPECT_EQ(sampled->columns, fresh->columns);
  }
  EXPECT_EQ(made.size(), 1u);
}

TEST(EmdCorrespondNode, RefusesModesOfAnotherMesh) {
  const MeshPtr grid = flatGrid(4), other = flatGrid(5);
  const auto param = test::projectedParameterization(grid, Vector3d::UnitX(), Vector3d::UnitY());
  auto modes = std::make_shared<VertexFields>(other->surface);
  modes->add("h1", linear(other->surface));
  const auto region = test::regionWhere(*param, *param, everywhere);
  try {
    test::runNode(
        "geobrush.emd_correspond",
        {{"region", region}, {"source", param}, {"target", param}, {"source_modes", modes}});
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'source_modes'");
  }
}

}  // namespace
}  // namespace geobrush
