// geobrush.render: the node wrapper around core's renderer (whose own
// analytic tests are in tests/core/render_test.cpp).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/render.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

struct Rendered {
  EvalReport report;
  ImagePtr image;
};

// load(mesh) -> render, with `params` on the render node.
Rendered renderFile(const std::filesystem::path& dir, const std::string& mesh, ParamMap params,
                    const std::string& overlay = "") {
  Graph graph;
  graph.file = dir / "graph.json";
  graph.nodes["load"] = {"geobrush.load_mesh", 1, {{"path", mesh}}};
  graph.nodes["render"] = {"geobrush.render", 1, std::move(params)};
  graph.connections.push_back({{"load", "mesh"}, {"render", "mesh"}});
  if (!overlay.empty()) {
    graph.nodes["load2"] = {"geobrush.load_mesh", 1, {{"path", overlay}}};
    graph.connections.push_back({{"load2", "mesh"}, {"render", "overlay"}});
  }
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  Rendered result{evaluator.evaluate(graph), nullptr};
  result.image = std::dynamic_pointer_cast<const Image>(evaluator.output("render", "image"));
  return result;
}

}  // namespace

TEST(RenderNode, WritesThePngItOutputs) {
  const auto dir = test::tempDir("render-node-png");
  auto result = renderFile(dir, test::meshPath("bunny_small.obj").string(),
                           {{"width", std::int64_t(200)},
                            {"height", std::int64_t(150)},
                            {"path", std::string("bunny.png")}});
  ASSERT_TRUE(result.report.ok) << result.report.error;
  ASSERT_TRUE(result.image);
  EXPECT_EQ(result.image->width, 200);
  EXPECT_EQ(result.image->height, 150);
  ASSERT_EQ(result.report.filesWritten.size(), 1u);
  EXPECT_EQ(result.report.filesWritten[0], dir / "bunny.png");
  const Image fromFile = readPng(dir / "bunny.png");
  EXPECT_EQ(fromFile.rgba, result.image->rgba);
  // The bunny fills a good part of the fitted view, but not all of it.
  EXPECT_GT(test::coverage(*result.image), 0.10);
  EXPECT_LT(test::coverage(*result.image), 0.90);
}

TEST(RenderNode, EmptyPathWritesNoFile) {
  const auto dir = test::tempDir("render-node-nopath");
  auto result = renderFile(
      dir, test::meshPath("sphere.obj").string(),
      {{"path", std::string()}, {"width", std::int64_t(64)}, {"height", std::int64_t(64)}});
  ASSERT_TRUE(result.report.ok) << result.report.error;
  EXPECT_TRUE(result.report.filesWritten.empty());
  EXPECT_TRUE(result.image);
}

// A unit sphere seen from any direction is a disc: its area fraction follows
// from the fitted camera (bounding sphere of the box, radius sqrt(3), fitted
// to the vertical field of view).
TEST(RenderNode, SphereCoverageMatchesTheCameraFit) {
  const auto dir = test::tempDir("render-node-sphere");
  auto result = renderFile(dir, test::meshPath("sphere.obj").string(),
                           {{"width", std::int64_t(400)},
                            {"height", std::int64_t(400)},
                            {"path", std::string()},
                            {"backend", std::string("cpu")}});
  ASSERT_TRUE(result.report.ok) << result.report.error;
  const double halfFov = 35.0 / 2 * M_PI / 180;
  const double distance = std::sqrt(3.0) / std::sin(halfFov);
  // Angular radius of the unit sphere from that distance, projected.
  const double discRadius = std::tan(std::asin(1.0 / distance)) / std::tan(halfFov);  // in NDC
  const double expected = M_PI * discRadius * discRadius / 4.0;
  EXPECT_NEAR(test::coverage(*result.image), expected, 0.02 * expected + 0.002);
}

TEST(RenderNode, FocusFramesTheBallAroundItsCentre) {
  // Framed by the unit ball (not the bounding box's larger one), the unit sphere's outline
  // touches the edges of a square picture: its disc covers pi / 4 of it.
  const auto dir = test::tempDir("render-node-focus");
  auto result = renderFile(dir, test::meshPath("sphere.obj").string(),
                           {{"width", std::int64_t(400)},
                            {"height", std::int64_t(400)},
                            {"path", std::string()},
                            {"backend", std::string("cpu")},
                            {"focus", Vec3{0, 0, 0}},
                            {"focus_radius", 1.0}});
  ASSERT_TRUE(result.report.ok) << result.report.error;
  EXPECT_NEAR(test::coverage(*result.image), M_PI / 4, 0.02);

  // A small ball on the surface fills the picture with it.
  auto close = renderFile(dir, test::meshPath("sphere.obj").string(),
                          {{"width", std::int64_t(200)},
                           {"height", std::int64_t(200)},
                           {"path", std::string()},
                           {"backend", std::string("cpu")},
                           {"azimuth", 0.0},
                           {"elevation", 0.0},
                           {"focus", Vec3{0, 0, 1}},
                           {"focus_radius", 0.1}});
  ASSERT_TRUE(close.report.ok) << close.report.error;
  EXPECT_EQ(test::coverage(*close.image), 1.0);
}

TEST(RenderNode, OverlayAndWireframeChangeThePicture) {
  const auto dir = test::tempDir("render-node-overlay");
  const ParamMap small{
      {"width", std::int64_t(160)}, {"height", std::int64_t(120)}, {"path", std::string()}};
  auto plain = renderFile(dir, test::meshPath("cube.obj").string(), small);
  auto overlay = renderFile(dir, test::meshPath("cube.obj").string(), small,
                            test::meshPath("torus.obj").string());
  ParamMap wire = small;
  wire["wireframe"] = true;
  auto wired = renderFile(dir, test::meshPath("cube.obj").string(), wire);
  ASSERT_TRUE(plain.report.ok && overlay.report.ok && wired.report.ok);
  EXPECT_NE(plain.image->rgba, overlay.image->rgba);
  EXPECT_NE(plain.image->rgba, wired.image->rgba);
}

// A mesh coloured by a field: emd_signal's g of the bunny, whose convex and concave parts show
// in red and blue, with the legend; a field the input lacks is refused naming the param.
TEST(RenderNode, ColoursTheMeshByAField) {
  const auto dir = test::tempDir("render-node-fields");
  const auto render = [&](const std::string& field) {
    Graph graph;
    graph.file = dir / "graph.json";
    graph.nodes["load"] = {
        "geobrush.load_mesh", 1, {{"path", test::meshPath("bunny_small.obj").string()}}};
    graph.nodes["signal"] = {"geobrush.emd_signal", 1, {{"area_normalize", true}}};
    graph.nodes["render"] = {"geobrush.render",
                             1,
                             {{"width", std::int64_t(240)},
                              {"height", std::int64_t(180)},
                              {"path", std::string()},
                              {"field", field}}};
    graph.connections.push_back({{"load", "mesh"}, {"signal", "mesh"}});
    graph.connections.push_back({{"load", "mesh"}, {"render", "mesh"}});
    graph.connections.push_back({{"signal", "signal"}, {"render", "fields"}});
    prepareGraph(graph, test::registry());
    Evaluator evaluator(test::registry());
    Rendered result{evaluator.evaluate(graph), nullptr};
    result.image = std::dynamic_pointer_cast<const Image>(evaluator.output("render", "image"));
    return result;
  };
  const Rendered colored = render("g");
  ASSERT_TRUE(colored.report.ok) << colored.report.error;
  int reddish = 0, bluish = 0;
  for (int y = 0; y < colored.image->height; ++y)
    for (int x = 0; x < colored.image->width; ++x) {
      const std::uint8_t* p = colored.image->pixel(x, y);
      if (p[0] > p[2] + 40) ++reddish;
      if (p[2] > p[0] + 40) ++bluish;
    }
  EXPECT_GT(reddish, 100);
  EXPECT_GT(bluish, 100);
  const Rendered missing = render("curvature");
  EXPECT_FALSE(missing.report.ok);
  EXPECT_TRUE(test::contains(missing.report.error, "param 'field'"));
  EXPECT_TRUE(test::contains(missing.report.error, "no field 'curvature'"));
}

TEST(RenderNode, CpuAndVulkanBackendsAgree) {
  const auto dir = test::tempDir("render-node-backends");
  auto cpu = renderFile(dir, test::meshPath("bunny_small.obj").string(),
                        {{"backend", std::string("cpu")}, {"path", std::string()}});
  auto vulkan = renderFile(dir, test::meshPath("bunny_small.obj").string(),
                           {{"backend", std::string("vulkan")}, {"path", std::string()}});
  ASSERT_TRUE(cpu.report.ok) << cpu.report.error;
  if (!vulkan.report.ok) GTEST_SKIP() << "no Vulkan device: " << vulkan.report.error;
  std::size_t close = 0;
  for (std::size_t i = 0; i < cpu.image->rgba.size(); i += 4)
    close += std::abs(int(cpu.image->rgba[i]) - int(vulkan.image->rgba[i])) <= 8;
  EXPECT_GT(double(close) / (cpu.image->rgba.size() / 4), 0.98);
}

// One source for the ranges: the node declares those of render.hpp, which `geobrush render`
// checks its options against.
TEST(RenderNode, DeclaresTheRangesOfRenderHpp) {
  const NodeType* type = test::registry().find("geobrush.render");
  ASSERT_NE(type, nullptr);
  const std::pair<const char*, RenderRange> ranges[] = {
      {"width", kRenderSizeRange},      {"height", kRenderSizeRange},
      {"azimuth", kRenderAzimuthRange}, {"elevation", kRenderElevationRange},
      {"fov", kRenderFovRange},         {"zoom", kRenderZoomRange}};
  for (const auto& [name, range] : ranges) {
    const ParamDecl* decl = type->findParam(name);
    ASSERT_NE(decl, nullptr) << name;
    EXPECT_EQ(decl->min, range.min) << name;
    EXPECT_EQ(decl->max, range.max) << name;
  }
}

TEST(RenderNode, NeverReplacesAFifo) {
  const auto dir = test::tempDir("render-node-fifo");
  const auto fifo = dir / "picture.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto result = renderFile(dir, test::meshPath("sphere.obj").string(),
                           {{"path", std::string("picture.png")},
                            {"width", std::int64_t(32)},
                            {"height", std::int64_t(32)}});
  EXPECT_FALSE(result.report.ok);
  EXPECT_TRUE(test::contains(result.report.error,
                             "node 'render' param 'path': " + test::quoted(fifo) + ": is a FIFO"));
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
}
