// geobrush.texture_roi: the texture copy's rasterization (CPU twin and Vulkan kernel), its
// barycentrics, its depth test on folds, its agreement with geobrush.roi, and the node.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <tuple>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/derived_store.hpp"
#include "roi.hpp"
#include "test_support.hpp"
#include "texture_raster_vulkan.hpp"
#include "texture_roi.hpp"

using namespace geobrush;

namespace {

std::shared_ptr<Parameterization> flatSquare(int n) {
  return test::heightFieldParameterization(n, [](double, double) { return 0.0; });
}

std::shared_ptr<Parameterization> shifted(const Parameterization& param, Eigen::Vector2d shift) {
  auto moved = std::make_shared<Parameterization>(param);
  for (auto& u : moved->uv)
    u += shift;
  return moved;
}

Strokes strokes(std::vector<Dab> dabs) {
  Strokes s;
  s.dabs = std::move(dabs);
  return s;
}

bool inSquare(const Eigen::Vector2d& u, const Eigen::Vector2d& shift = Eigen::Vector2d::Zero()) {
  return ((u - shift).array().abs() <= 1).all();
}

// Distance from u to the nearest dab outline (all dabs add).
double toOutline(const Strokes& s, const Eigen::Vector2d& u) {
  double distance = INFINITY;
  for (const Dab& dab : s.dabs)
    distance = std::min(distance, std::abs((u - dab.center).norm() - dab.radius));
  return distance;
}

// Distance from u to the outline of the square [-1, 1]^2 moved by `shift`.
double toSquareOutline(const Eigen::Vector2d& u, const Eigen::Vector2d& shift) {
  const Eigen::Vector2d d = (u - shift).cwiseAbs() - Eigen::Vector2d::Ones();
  return inSquare(u, shift) ? -d.maxCoeff() : d.cwiseMax(0.0).norm();
}

double longestUvEdge(const Parameterization& param) {
  const TriMesh& mesh = param.canvas->surface;
  double longest = 0;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    longest = std::max(longest, (param.uv[std::size_t(mesh.to_vertex_handle(h).idx())] -
                                 param.uv[std::size_t(mesh.from_vertex_handle(h).idx())])
                                    .norm());
  }
  return longest;
}

std::vector<int> symmetricDifference(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> out;
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

// Two triangles on their own vertices whose uv overlap around the origin, at heights z0 and z1
// along the frame's normal (+z).
std::shared_ptr<Parameterization> foldedPair(double z0, double z1) {
  auto canvas = std::make_shared<Canvas>();
  TriMesh& mesh = canvas->surface;
  const std::vector<Eigen::Vector2d> uv = {{-1, -1}, {1, -1}, {0, 1}, {-1, 1}, {0, -1}, {1, 1}};
  for (std::size_t v = 0; v < uv.size(); ++v)
    mesh.add_vertex(TriMesh::Point(uv[v].x(), uv[v].y(), v < 3 ? z0 : z1));
  mesh.add_face(TriMesh::VertexHandle(0), TriMesh::VertexHandle(1), TriMesh::VertexHandle(2));
  // Clockwise in the domain: a face the projection turned over.
  mesh.add_face(TriMesh::VertexHandle(3), TriMesh::VertexHandle(5), TriMesh::VertexHandle(4));
  for (int v = 0; v < 6; ++v)
    canvas->sourceVertex.push_back(v);
  auto param = std::make_shared<Parameterization>();
  param->canvas = canvas;
  param->uv = uv;
  param->normal.assign(uv.size(), Eigen::Vector3d::UnitZ());
  return param;
}

// Rasterizes with both kernels and expects the same faces and weights, bit for bit.
void expectKernelsAgree(const Parameterization& param, int size) {
  const DomainGrid grid = textureGrid(param, size);
  const RasterFaces raster = rasterFaces(param, grid);
  std::vector<std::uint32_t> cpuFace, gpuFace;
  std::vector<std::int64_t> cpuWeight, gpuWeight;
  rasterizeCpu(raster, cpuFace, cpuWeight);
  rasterizeVulkan(raster, gpuFace, gpuWeight);
  ASSERT_EQ(cpuFace.size(), std::size_t(size) * std::size_t(size));
  EXPECT_EQ(cpuFace, gpuFace);
  EXPECT_EQ(cpuWeight, gpuWeight);
  const auto covered = std::count_if(cpuFace.begin(), cpuFace.end(), [](auto f) { return f; });
  // The canvases here cover a quarter to four fifths of the texture (their disc's square).
  EXPECT_GT(covered, std::ptrdiff_t(cpuFace.size() / 5));
}

#define SKIP_WITHOUT_VULKAN()                                                              \
  do {                                                                                     \
    if (!textureRasterVulkanAvailable()) {                                                 \
      GTEST_SKIP() << "Vulkan is unavailable: " << textureRasterVulkanUnavailableReason(); \
    }                                                                                      \
  } while (false)

}  // namespace

TEST(TextureGrid, SpansTheSourceDiscAndABorderCentredOnTheOrigin) {
  auto param = flatSquare(10);  // R = sqrt2
  const DomainGrid grid = textureGrid(*param, 64);
  EXPECT_EQ(grid.width, 64);
  EXPECT_EQ(grid.height, 64);
  const double radius = std::sqrt(2.0);
  EXPECT_NEAR(grid.spacing, 2 * radius / (64 - 2 * kTextureBorder), 1e-15);
  // The disc's extent ends where the border's texels begin, on either side.
  EXPECT_NEAR(grid.position(kTextureBorder, 0).x() - grid.spacing / 2, -radius, 1e-14);
  EXPECT_NEAR(grid.position(0, 63 - kTextureBorder).y() + grid.spacing / 2, radius, 1e-14);
  // The texture's centre, between texels 31 and 32, is uv (0, 0), as E3 puts it.
  EXPECT_NEAR((grid.position(31, 31) + grid.position(32, 32)).norm(), 0, 1e-15);
  EXPECT_THROW(textureGrid(*param, 8), TextureRoiError);
  EXPECT_THROW(textureGrid(*param, 8192), TextureRoiError);
}

TEST(TextureRaster, APlaneGridCoversItsSquareWithoutGaps) {
  auto param = flatSquare(16);
  const CanvasTexture texture = rasterize(*param, textureGrid(*param, 64), TextureKernel::Cpu);
  const DomainGrid& grid = texture.grid;
  // Every texel centre in the square [-1, 1]^2 lies in a face, those on the quads' diagonals
  // included, which the fill rule gives to one of the two faces there; none outside it does.
  std::size_t inside = 0;
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i) {
      const Eigen::Vector2d u = grid.position(i, j);
      const std::uint32_t face = texture.face[grid.index(i, j)];
      if (u.cwiseAbs().maxCoeff() < 1 - 1e-9) {
        ++inside;
        ASSERT_NE(face, 0u) << i << " " << j;
      } else if (u.cwiseAbs().maxCoeff() > 1 + 1e-9) {
        ASSERT_EQ(face, 0u) << i << " " << j;
      }
    }
  EXPECT_GT(inside, grid.nodeCount() / 3);
}

TEST(TextureRaster, BarycentricsReproduceTheTexelCentres) {
  for (const auto& param : {flatSquare(37), test::terrainParameterization()}) {
    const int size = 256;
    const CanvasTexture texture = rasterize(*param, textureGrid(*param, size), TextureKernel::Cpu);
    const DomainGrid& grid = texture.grid;
    const TriMesh& mesh = param->canvas->surface;
    // Snapping moves each corner by at most half a fixed-point step per axis, and the texel's
    // uv is a convex combination of the moved corners: the same combination of the true corners
    // is off by at most that much.
    const double bound = std::sqrt(2.0) / (2 << kSubtexelBits) * grid.spacing;
    double worst = 0;
    std::size_t covered = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const std::size_t t = grid.index(i, j);
        if (texture.face[t] == 0) continue;
        ++covered;
        const Eigen::Vector3d b = texture.barycentric(t);
        EXPECT_GE(b.minCoeff(), 0);
        EXPECT_NEAR(b.sum(), 1, 1e-12);
        Eigen::Vector2d u = Eigen::Vector2d::Zero();
        int k = 0;
        for (auto v : mesh.fv_range(TriMesh::FaceHandle(int(texture.face[t]) - 1)))
          u += b[k++] * param->uv[std::size_t(v.idx())];
        worst = std::max(worst, (u - grid.position(i, j)).norm());
      }
    EXPECT_GT(covered, grid.nodeCount() / 3);
    EXPECT_LE(worst, bound * (1 + 1e-9));
    EXPECT_LT(bound, grid.spacing / size);  // within 1/N of a texel, as the spec asks
  }
}

TEST(TextureRaster, AFoldKeepsTheHigherFace) {
  for (const auto& [z0, z1, winner] :
       {std::tuple{0.0, 1.0, 2u}, std::tuple{1.0, 0.0, 1u}, std::tuple{0.5, 0.5, 1u}}) {
    auto param = foldedPair(z0, z1);
    const CanvasTexture texture = rasterize(*param, textureGrid(*param, 32), TextureKernel::Cpu);
    const DomainGrid& grid = texture.grid;
    EXPECT_EQ(texture.flipped, (std::vector<std::uint8_t>{0, 1}));
    std::size_t overlap = 0;
    for (int j = 0; j < grid.height; ++j)
      for (int i = 0; i < grid.width; ++i) {
        const Eigen::Vector2d u = grid.position(i, j);
        // Strictly inside both triangles (edges left out: the fill rule decides there).
        const bool inFirst =
            u.y() > -1 + 1e-9 && 2 * u.x() + u.y() < 1 - 1e-9 && -2 * u.x() + u.y() < 1 - 1e-9;
        const bool inSecond =
            u.y() < 1 - 1e-9 && 2 * u.x() + u.y() > -1 + 1e-9 && -2 * u.x() + u.y() > -1 + 1e-9;
        if (!(inFirst && inSecond)) continue;
        ++overlap;
        EXPECT_EQ(texture.face[grid.index(i, j)], winner) << z0 << " " << z1;
      }
    EXPECT_GT(overlap, 50u);
  }
}

TEST(TextureRasterVulkan, MatchesTheCpuTwinOnAPlaneGrid) {
  SKIP_WITHOUT_VULKAN();
  expectKernelsAgree(*flatSquare(40), 128);
  expectKernelsAgree(*shifted(*flatSquare(23), {0.37, -0.21}), 100);  // tiles cut by the edge
}

TEST(TextureRasterVulkan, MatchesTheCpuTwinOnTheMountainCanvas) {
  SKIP_WITHOUT_VULKAN();
  expectKernelsAgree(*test::terrainParameterization(), 512);
}

TEST(TextureRasterVulkan, MatchesTheCpuTwinOnAFold) {
  SKIP_WITHOUT_VULKAN();
  expectKernelsAgree(*foldedPair(0, 1), 64);
  expectKernelsAgree(*foldedPair(1, 0), 64);
}

// Q on the texel grid is the painted points covered by both canvases, except where a texel centre
// lies within one texel of a canvas outline (its snapped corners decide there); the vertex sets
// equal roi's except within a texel diagonal and a face of the brush or canvas outline (R_in is
// made of whole faces here).
TEST(TextureRoi, EqualsRoiExceptOnTheOutlines) {
  auto source = flatSquare(60);
  const Eigen::Vector2d shift(0.4, 0.25);
  auto target = shifted(*source, shift);
  const Strokes s = strokes({{{0.1, -0.2}, 0.45, false}, {{0.5, 0.3}, 0.4, false}});
  const TextureRoiResult texture = textureRoi(s, *source, *target, {128, TextureKernel::Cpu});
  const Region2D& region = texture.region;
  const DomainGrid& grid = region.grid;
  std::size_t inside = 0;
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i) {
      const Eigen::Vector2d u = grid.position(i, j);
      const bool expected = s.contains(u) && inSquare(u) && inSquare(u, shift);
      inside += region.inside[grid.index(i, j)];
      if (std::min(std::abs(toSquareOutline(u, {0, 0})), std::abs(toSquareOutline(u, shift))) >
          grid.spacing) {
        EXPECT_EQ(region.inside[grid.index(i, j)] != 0, expected) << i << " " << j;
      }
    }
  EXPECT_GT(inside, 1000u);

  const RoiResult roi = paintRegion(s, *source, *target, RoiOptions{256});
  ASSERT_FALSE(roi.region.sourceVertices.empty());
  const double tolerance = std::sqrt(2.0) * grid.spacing + longestUvEdge(*source);
  auto nearAnOutline = [&](const Eigen::Vector2d& u) {
    return toOutline(s, u) <= tolerance || std::abs(toSquareOutline(u, {0, 0})) <= tolerance ||
           std::abs(toSquareOutline(u, shift)) <= tolerance;
  };
  const auto sourceDiff = symmetricDifference(region.sourceVertices, roi.region.sourceVertices);
  for (int v : sourceDiff)
    EXPECT_TRUE(nearAnOutline(source->uv[std::size_t(v)])) << "source vertex " << v;
  const auto targetDiff = symmetricDifference(region.targetVertices, roi.region.targetVertices);
  for (int v : targetDiff)
    EXPECT_TRUE(nearAnOutline(target->uv[std::size_t(v)])) << "target vertex " << v;
  EXPECT_LT(sourceDiff.size(), region.sourceVertices.size() / 4);
  EXPECT_LT(targetDiff.size(), region.targetVertices.size() / 4);
  // The draft support holds R_in, as roi's does.
  EXPECT_TRUE(std::includes(region.draftSupport.begin(), region.draftSupport.end(),
                            region.sourceVertices.begin(), region.sourceVertices.end()));
}

TEST(TextureRoi, EqualsRoiOnTheMountainCanvasExceptOnTheOutline) {
  auto param = test::terrainParameterization();
  const DomainGrid grid = textureGrid(*param, 512);
  const Strokes s = strokes({{{0, 0}, 20 * grid.spacing, false}});
  const TextureRoiResult texture = textureRoi(s, *param, *param, {512, TextureKernel::Cpu});
  const RoiResult roi = paintRegion(s, *param, *param, RoiOptions{512});
  ASSERT_FALSE(texture.region.empty());
  const double tolerance = std::sqrt(2.0) * grid.spacing + longestUvEdge(*param);
  const auto diff = symmetricDifference(texture.region.sourceVertices, roi.region.sourceVertices);
  for (int v : diff)
    EXPECT_LE(toOutline(s, param->uv[std::size_t(v)]), tolerance) << v;
}

namespace {

test::NodeRun runTextureRoi(const Strokes& s, const ParameterizationPtr& source,
                            const ParameterizationPtr& target, const std::string& kernel) {
  return test::runNode(
      "geobrush.texture_roi",
      {{"strokes", std::make_shared<const Strokes>(s)}, {"source", source}, {"target", target}},
      {{"kernel", kernel}, {"texture_size", std::int64_t(256)}});
}

}  // namespace

TEST(TextureRoiNode, RunsOnTheMountainTheSameEveryTimeAndOnEitherKernel) {
  const ParameterizationPtr param = test::terrainParameterization();
  const Strokes s = strokes({{{0, 0}, 20 * textureGrid(*param, 256).spacing, false}});
  const auto first = runTextureRoi(s, param, param, "cpu").get<Region2D>("region");
  const auto second = runTextureRoi(s, param, param, "cpu").get<Region2D>("region");
  ASSERT_TRUE(first && second);
  EXPECT_FALSE(first->empty());
  EXPECT_EQ(first->contentHash(), second->contentHash());
  EXPECT_EQ(first->inside, second->inside);
  EXPECT_EQ(first->sourceVertices, second->sourceVertices);
  EXPECT_EQ(first->draftSupport, second->draftSupport);
  if (textureRasterVulkanAvailable()) {
    const auto vulkan = runTextureRoi(s, param, param, "vulkan").get<Region2D>("region");
    const auto automatic = runTextureRoi(s, param, param, "auto").get<Region2D>("region");
    EXPECT_EQ(vulkan->contentHash(), first->contentHash());
    EXPECT_EQ(automatic->contentHash(), first->contentHash());
  }
}

TEST(TextureRoiNode, StrokesOverNothingGiveAnEmptyRegionAndAWarning) {
  const ParameterizationPtr param = flatSquare(10);
  const auto run = runTextureRoi(strokes({{{5, 5}, 0.3, false}}), param, param, "cpu");
  const auto region = run.get<Region2D>("region");
  ASSERT_TRUE(region);
  EXPECT_TRUE(region->empty());
  EXPECT_TRUE(region->targetVertices.empty());
  EXPECT_EQ(std::count(region->inside.begin(), region->inside.end(), 1), 0);
  EXPECT_EQ(run.warnings.size(), 2u);
}

TEST(TextureRoiNode, ABadKernelNamesTheParam) {
  const ParameterizationPtr param = flatSquare(10);
  try {
    runTextureRoi(strokes({{{0, 0}, 0.3, false}}), param, param, "opencl");
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'kernel'");
    EXPECT_NE(std::string(e.what()).find("opencl"), std::string::npos);
  }
}

TEST(TextureRoiNode, ASourceWithoutExtentNamesTheSourcePort) {
  auto param = flatSquare(4);
  for (auto& u : param->uv)
    u.setZero();
  try {
    runTextureRoi(strokes({{{0, 0}, 0.3, false}}), param, flatSquare(4), "cpu");
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'source'");
  }
}

// In a child process, where the device is forced to one that does not exist.
TEST(TextureRoiNodeDeathTest, VulkanWithoutADeviceNamesTheParamAndAutoFallsBack) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        ::setenv("GEOBRUSH_VK_DEVICE", "no such device", 1);
        const ParameterizationPtr param = flatSquare(10);
        const Strokes s = strokes({{{0, 0}, 0.3, false}});
        try {
          runTextureRoi(s, param, param, "vulkan");
          std::exit(1);
        } catch (const NodeError& e) {
          std::fprintf(stderr, "%s: %s\n", e.where().c_str(), e.what());
        }
        const auto region = runTextureRoi(s, param, param, "auto").get<Region2D>("region");
        std::exit(region && !region->empty() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "param 'kernel': vulkan needs a Vulkan device");
}

// The node keeps nothing: both textures and the source locator are the framework's derived
// data, so a new dab only redoes the copy and a new target canvas rasterizes only the target.
TEST(TextureRoiNode, ANewDabOnlyRedoesTheCopy) {
  auto source = flatSquare(30);
  const NodeType* type = test::registry().find("geobrush.texture_roi");
  ASSERT_TRUE(type);
  auto store = std::make_shared<DerivedStore>();
  const ParamMap params = {{"kernel", std::string("cpu")}, {"texture_size", std::int64_t(64)}};
  Strokes s = strokes({{{0.3, 0.1}, 0.5, false}});
  ParameterizationPtr target = shifted(*source, {0.5, 0.1});
  std::uint64_t builds = 0;
  for (int step = 0; step < 3; ++step) {
    SCOPED_TRACE(step);
    if (step == 1) s.dabs.push_back({{-0.2, 0.0}, 0.3, false});
    if (step == 2) target = shifted(*source, {0.1, 0.2});
    auto node = type->create();
    test::DirectContext ctx(
        *type,
        {{"strokes", std::make_shared<const Strokes>(s)}, {"source", source}, {"target", target}},
        params, store);
    node->compute(ctx);
    const auto region = std::dynamic_pointer_cast<const Region2D>(ctx.outputs["region"]);
    ASSERT_TRUE(region);
    const TextureRoiResult fresh = textureRoi(s, *source, *target, {64, TextureKernel::Cpu});
    EXPECT_EQ(region->contentHash(), fresh.region.contentHash());
    // First both textures and the source locator; then nothing; then the target's texture.
    const std::uint64_t expected[] = {3, 0, 1};
    EXPECT_EQ(store->builds() - builds, expected[step]);
    builds = store->builds();
  }
}

TEST(TextureRoi, DabsOutsideTheCanvasesAreReportedAndChangeNothing) {
  auto param = flatSquare(20);
  const TextureRoiOptions options{64, TextureKernel::Cpu};
  const TextureRoiResult result =
      textureRoi(strokes({{{5, 5}, 0.5, false}, {{0, 0}, 0.3, false}, {{-3, 0}, 0.2, false}}),
                 *param, *param, options);
  EXPECT_EQ(result.dabsOutside, (std::vector<int>{0, 2}));
  const TextureRoiResult inside =
      textureRoi(strokes({{{0, 0}, 0.3, false}}), *param, *param, options);
  EXPECT_EQ(result.region.contentHash(), inside.region.contentHash());
  EXPECT_FALSE(inside.region.empty());
}
