#include "emd_transfer.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "emd_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/vertex_fields.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// Two target modes, a residue and two sampled source modes over six vertices, the first four in
// the region.
struct Columns {
  std::vector<double> h1{1, 2, 3, 4, 5, 6}, h2{-1, 0.5, 0, 2, 1, 1}, r{10, 10, 11, 12, 13, 14};
  std::vector<double> s1{0.5, -0.5, 1, 2, 9, 9}, s2{3, 2, 1, 0, 9, 9};
  std::vector<double> region{1, 1, 1, 1, 0, 0};
  EmdTransferResult run(std::vector<double> gains, std::vector<double> keep) const {
    return transferSignal({&h1, &h2}, r, {&s1, &s2}, region, {gains, keep});
  }
};

// T5: with every gain 0 and the target's detail kept (Eq. 3), g^ is the target's own g.
TEST(EmdTransfer, ZeroGainsGiveTheTargetSignal) {
  const Columns c;
  const EmdTransferResult result = c.run({0, 0}, {1, 1});
  for (std::size_t v = 0; v < 6; ++v) {
    EXPECT_NEAR(result.signal[v], c.r[v] + c.h1[v] + c.h2[v], 1e-12);
    EXPECT_EQ(result.detail[v], 0.0);
  }
}

// Eqs. 3-5: b = 0 drops a target mode on the region (Eq. 5), the gains weigh the source modes;
// off the region the target is untouched.
TEST(EmdTransfer, MixesScalesByTheGainsAndSwitches) {
  const Columns c;
  const EmdTransferResult result = c.run({2, 0.5}, {0, 1});
  for (std::size_t v = 0; v < 6; ++v) {
    const double d = 2 * c.s1[v] + 0.5 * c.s2[v];
    if (c.region[v] != 0) {
      EXPECT_NEAR(result.detail[v], d, 1e-12);
      EXPECT_NEAR(result.signal[v], c.r[v] + c.h2[v] + d, 1e-12);
    } else {
      EXPECT_EQ(result.detail[v], 0.0);
      EXPECT_NEAR(result.signal[v], c.r[v] + c.h1[v] + c.h2[v], 1e-12);
    }
  }
}

// T6 (the signal's half): g^ is affine in the gains.
TEST(EmdTransfer, IsAffineInTheGains) {
  const Columns c;
  const auto zero = c.run({0, 0}, {1, 0}), once = c.run({1.5, -0.7}, {1, 0}),
             twice = c.run({3, -1.4}, {1, 0});
  for (std::size_t v = 0; v < 6; ++v)
    EXPECT_NEAR(twice.signal[v] - zero.signal[v], 2 * (once.signal[v] - zero.signal[v]), 1e-12);
}

TEST(EmdTransfer, RefusesListsThatDoNotMatchTheModes) {
  const Columns c;
  EXPECT_THROW(c.run({1}, {1, 1}), std::invalid_argument);
  EXPECT_THROW(c.run({1, 1}, {1, 1, 1}), std::invalid_argument);
}

// The node on a real mesh's own decomposition (emd_signal, emd, emd_correspond onto itself with
// k = 1): unit gains and switches give back g.
TEST(EmdTransferNode, GivesBackTheSignalOfARealMeshTransferredOntoItself) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto signal =
      test::runNode("geobrush.emd_signal", {{"mesh", bunny}}).get<VertexFields>("signal");
  const auto modes = test::runNode("geobrush.emd", {{"mesh", bunny}, {"signal", signal}})
                         .get<VertexFields>("modes");
  const auto param =
      test::projectedParameterization(bunny, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
  const auto region =
      test::regionWhere(*param, *param, [](const Eigen::Vector2d&) { return true; });
  const auto sampled =
      test::runNode(
          "geobrush.emd_correspond",
          {{"region", region}, {"source", param}, {"target", param}, {"source_modes", modes}},
          {{"neighbours", std::int64_t(1)}})
          .get<VertexFields>("sampled");
  ASSERT_TRUE(signal && modes && sampled);
  // Where two vertices project onto one point, the nearest is the lower one: compare there.
  const auto& nearest = sampled->column("nearest");
  const test::NodeRun run =
      test::runNode("geobrush.emd_transfer", {{"target_modes", modes}, {"sampled", sampled}},
                    {{"keep_target", std::vector<double>{0, 0, 0}}});
  const auto transferred = run.get<VertexFields>("signal");
  ASSERT_TRUE(transferred);
  EXPECT_EQ(transferred->names(), (std::vector<std::string>{"g_hat", "detail", "region"}));
  const auto& g = signal->column("g");
  double scale = 0;
  for (double value : g)
    scale = std::max(scale, std::abs(value));
  std::size_t own = 0;
  for (std::size_t v = 0; v < g.size(); ++v) {
    if (std::size_t(nearest[v]) != v) continue;
    ++own;
    EXPECT_NEAR(transferred->column("g_hat")[v], g[v], 1e-12 * scale) << v;
  }
  EXPECT_GT(own, g.size() * 9 / 10);
}

TEST(EmdTransferNode, NamesTheListThatDoesNotFitTheModes) {
  const MeshPtr grid = test::heightGrid(3, [](double, double) { return 0.0; });
  auto modes = std::make_shared<VertexFields>(grid->surface);
  modes->add("h1", std::vector<double>(16, 1.0));
  modes->add("r", std::vector<double>(16, 0.0));
  auto sampled = std::make_shared<VertexFields>(grid->surface);
  sampled->add("h1", std::vector<double>(16, 1.0));
  sampled->add("region", std::vector<double>(16, 1.0));
  try {
    test::runNode("geobrush.emd_transfer", {{"target_modes", modes}, {"sampled", sampled}},
                  {{"keep_target", std::vector<double>{1}}});
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'gains'");
    EXPECT_TRUE(test::contains(e.what(), "3 entries for 1 source modes"));
  }
}

}  // namespace
}  // namespace geobrush
