// geobrush.uv_lines: coordinate lines as vertex colours.
#include <gtest/gtest.h>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "test_support.hpp"
#include "uv_lines.hpp"

using namespace geobrush;

TEST(UvLines, LinesFallOnMultiplesOfTheSpacing) {
  // 8 x 8 quads over [-1, 1]^2: vertices every 0.25 in u and v.
  auto param = test::heightFieldParameterization(8, [](double, double) { return 0.0; });
  UvLinesOptions options;
  options.spacing = 0.5;
  const UvLinesResult result = paintUvLines(*param, options);
  ASSERT_EQ(result.mesh.vertexColors.size(), param->uv.size());
  for (std::size_t v = 0; v < param->uv.size(); ++v) {
    const auto& uv = param->uv[v];
    const bool onU = std::abs(uv.x() / 0.5 - std::round(uv.x() / 0.5)) < 1e-9;
    const bool onV = std::abs(uv.y() / 0.5 - std::round(uv.y() / 0.5)) < 1e-9;
    const Rgb expected = onU ? options.uLine : onV ? options.vLine : options.surface;
    EXPECT_EQ(result.mesh.vertexColors[v], expected) << uv.transpose();
  }
  EXPECT_TRUE(result.mesh.surface.n_faces() == param->canvas->surface.n_faces());
}

TEST(UvLines, AutomaticSpacingIsATenthOfTheDomain) {
  auto param = test::terrainParameterization();
  const UvLinesResult result = paintUvLines(*param);
  Eigen::Vector2d lo = param->uv.front(), hi = lo;
  for (const auto& p : param->uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  EXPECT_DOUBLE_EQ(result.spacing, (hi - lo).maxCoeff() / 10);
  // Lines of 15% width in both directions colour about 28% of the vertices.
  std::size_t lined = 0;
  for (const auto& c : result.mesh.vertexColors)
    lined += c != UvLinesOptions{}.surface;
  const double fraction = double(lined) / double(param->uv.size());
  EXPECT_GT(fraction, 0.2);
  EXPECT_LT(fraction, 0.36);
}

TEST(UvLines, NodeAndBadInput) {
  auto param = test::heightFieldParameterization(4, [](double, double) { return 0.0; });
  const NodeType* type = test::registry().find("geobrush.uv_lines");
  ASSERT_NE(type, nullptr);
  test::DirectContext ctx(*type, {{"parameterization", param}});
  type->create()->compute(ctx);
  auto mesh = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["mesh"]);
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->vertexColors.size(), param->uv.size());
  auto broken = std::make_shared<Parameterization>(*param);
  broken->uv[2].x() = std::nan("");
  test::DirectContext bad(*type, {{"parameterization", broken}});
  try {
    type->create()->compute(bad);
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'parameterization'");
  }
}
