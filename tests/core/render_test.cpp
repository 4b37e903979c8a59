#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <thread>

#include "geobrush/gpu/vulkan_context.hpp"
#include "geobrush/render.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using ::testing::HasSubstr;

// Read with OpenMesh directly, so these tests do not depend on mesh_io.
MeshPtr loadMesh(const std::string& name) {
  TriMesh surface;
  if (!OpenMesh::IO::read_mesh(surface, test::meshPath(name).string()))
    throw std::runtime_error("cannot read " + test::meshPath(name).string());
  return std::make_shared<const Mesh>(std::move(surface));
}

MeshPtr makeMesh(const std::vector<Eigen::Vector3d>& points,
                 const std::vector<std::array<int, 3>>& faces, std::vector<Rgb> colors = {}) {
  TriMesh surface;
  std::vector<TriMesh::VertexHandle> vertices;
  for (const auto& p : points)
    vertices.push_back(surface.add_vertex(toPoint(p)));
  for (const auto& f : faces)
    surface.add_face(vertices[f[0]], vertices[f[1]], vertices[f[2]]);
  return std::make_shared<const Mesh>(std::move(surface), std::move(colors));
}

// The box [centre - half, centre + half], faces oriented outwards.
MeshPtr box(const Eigen::Vector3d& centre, double half, std::vector<Rgb> colors = {}) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i)
    points.push_back(centre +
                     half * Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  const std::vector<std::array<int, 3>> faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return makeMesh(points, faces, std::move(colors));
}

// A square in the plane z = 0, facing +z (or -z when `flipped`).
MeshPtr square(double half, bool flipped = false) {
  const std::vector<Eigen::Vector3d> points = {
      {-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  if (flipped) return makeMesh(points, {{0, 2, 1}, {0, 3, 2}});
  return makeMesh(points, {{0, 1, 2}, {0, 2, 3}});
}

RenderOptions options(RenderBackend backend, int width = 320, int height = 240) {
  RenderOptions o;
  o.backend = backend;
  o.width = width;
  o.height = height;
  return o;
}

#define SKIP_WITHOUT_VULKAN()                  \
  if (gpu::VulkanContext::shared() == nullptr) \
  GTEST_SKIP() << "Vulkan is unavailable: " << gpu::VulkanContext::unavailableReason()

bool isBackground(const Image& image, int x, int y, const std::array<std::uint8_t, 3>& bg) {
  const std::uint8_t* p = image.pixel(x, y);
  return p[0] == bg[0] && p[1] == bg[1] && p[2] == bg[2];
}

std::vector<bool> coverage(const Image& image, const std::array<std::uint8_t, 3>& bg) {
  std::vector<bool> covered(std::size_t(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      covered[std::size_t(y) * image.width + x] = !isBackground(image, x, y, bg);
  return covered;
}

// A pixel next to (4-neighbourhood) a pixel of other coverage.
bool onSilhouette(const std::vector<bool>& covered, int width, int height, int x, int y) {
  const bool here = covered[std::size_t(y) * width + x];
  for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
    const int nx = x + dx, ny = y + dy;
    if (nx >= 0 && ny >= 0 && nx < width && ny < height &&
        covered[std::size_t(ny) * width + nx] != here)
      return true;
  }
  return false;
}

struct Agreement {
  double closeFraction = 0;             // pixels with every channel within the tolerance
  int coverageDifferences = 0;          // pixels covered in one image only
  int coverageDifferencesInterior = 0;  // ... and on neither image's silhouette
};

Agreement compare(const Image& a, const Image& b, const std::array<std::uint8_t, 3>& bg,
                  int tolerance) {
  Agreement result;
  if (a.width != b.width || a.height != b.height) {
    ADD_FAILURE() << "the images differ in size";
    return result;
  }
  const auto coveredA = coverage(a, bg);
  const auto coveredB = coverage(b, bg);
  int close = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const std::uint8_t* p = a.pixel(x, y);
      const std::uint8_t* q = b.pixel(x, y);
      bool near = true;
      for (int c = 0; c < 4; ++c)
        near = near && std::abs(int(p[c]) - int(q[c])) <= tolerance;
      close += near;
      const std::size_t i = std::size_t(y) * a.width + x;
      if (coveredA[i] == coveredB[i]) continue;
      ++result.coverageDifferences;
      if (!onSilhouette(coveredA, a.width, a.height, x, y) &&
          !onSilhouette(coveredB, a.width, a.height, x, y))
        ++result.coverageDifferencesInterior;
    }
  }
  result.closeFraction = double(close) / (double(a.width) * a.height);
  return result;
}

std::array<std::uint8_t, 3> toBytes(const Rgb& color) {
  std::array<std::uint8_t, 3> bytes;
  for (int c = 0; c < 3; ++c)
    bytes[c] = std::uint8_t(std::lround(color[c] * 255));
  return bytes;
}

const Rgb kBlack{0, 0, 0};

// Zoom 8 puts the eye inside the bounding sphere, so triangles are clipped
// at the near plane and far outside the viewport.
TEST(RenderTest, VulkanAndCpuAgreeOnTheBunny) {
  SKIP_WITHOUT_VULKAN();
  const auto bunny = loadMesh("bunny_small.obj");
  for (double zoom : {1.0, 8.0}) {
    for (bool wireframe : {false, true}) {
      SCOPED_TRACE("zoom " + std::to_string(zoom) + (wireframe ? ", wireframe" : ""));
      std::vector<RenderItem> items = {{bunny, {0.9f, 0.6f, 0.3f}, wireframe}};
      auto o = options(RenderBackend::Vulkan, 400, 300);
      o.view.zoom = zoom;
      o.view.azimuthDeg = 100;
      o.background = kBlack;
      const RenderResult vulkan = renderMeshes(items, o);
      o.backend = RenderBackend::Cpu;
      const RenderResult cpu = renderMeshes(items, o);
      ASSERT_EQ(vulkan.backend, "vulkan");
      ASSERT_EQ(cpu.backend, "cpu");

      const Agreement agreement = compare(vulkan.image, cpu.image, toBytes(kBlack), 3);
      EXPECT_GE(agreement.closeFraction, 0.99);
      EXPECT_EQ(agreement.coverageDifferencesInterior, 0);
      // Silhouette differences come from rounding at pixel centres on edges: a handful.
      EXPECT_LE(agreement.coverageDifferences, 40);
    }
  }
}

TEST(RenderTest, VulkanAndCpuAgreeOnVertexColoursAndOverlaps) {
  SKIP_WITHOUT_VULKAN();
  const auto bunny = loadMesh("bunny_small.obj");
  std::vector<Rgb> colors;
  for (auto v : bunny->surface.vertices()) {
    const auto& p = bunny->surface.point(v);
    colors.push_back({float(0.5 + 0.5 * std::sin(p[0])), float(0.5 + 0.5 * std::cos(p[1])),
                      float(0.5 + 0.5 * std::sin(p[2] * 2))});
  }
  const auto colored = std::make_shared<const Mesh>(bunny->surface, colors);
  const std::vector<RenderItem> items = {{colored}, {box({0, 1, 0}, 3), {0.2f, 0.4f, 0.9f}, true}};
  auto o = options(RenderBackend::Vulkan, 300, 300);
  o.view = {.azimuthDeg = -70, .elevationDeg = 35, .fovDeg = 50, .zoom = 1.4};
  o.background = kBlack;
  const Image vulkan = renderMeshes(items, o).image;
  o.backend = RenderBackend::Cpu;
  const Image cpu = renderMeshes(items, o).image;
  const Agreement agreement = compare(vulkan, cpu, toBytes(kBlack), 3);
  EXPECT_GE(agreement.closeFraction, 0.99);
  EXPECT_EQ(agreement.coverageDifferencesInterior, 0);
}

class RenderBackendTest : public ::testing::TestWithParam<RenderBackend> {
 protected:
  void SetUp() override {
    if (GetParam() == RenderBackend::Vulkan) SKIP_WITHOUT_VULKAN();
  }
};

INSTANTIATE_TEST_SUITE_P(Backends, RenderBackendTest,
                         ::testing::Values(RenderBackend::Vulkan, RenderBackend::Cpu),
                         [](const auto& info) {
                           return info.param == RenderBackend::Vulkan ? "Vulkan" : "Cpu";
                         });

// Seen head-on, the unit cube's silhouette is its front face, whose extent
// follows from the documented framing: the bounding sphere (radius √3/2)
// fits the narrower field of view at distance r / sin(half angle) / zoom.
TEST_P(RenderBackendTest, HeadOnCubeCoversTheExpectedRectangle) {
  struct Case {
    int width, height;
    double fovDeg, zoom;
  };
  for (const Case& c : {Case{320, 200, 35, 1}, Case{200, 320, 35, 1}, Case{256, 256, 60, 1.7}}) {
    SCOPED_TRACE(std::to_string(c.width) + "x" + std::to_string(c.height));
    auto o = options(GetParam(), c.width, c.height);
    o.view = {.azimuthDeg = 0, .elevationDeg = 0, .fovDeg = c.fovDeg, .zoom = c.zoom};
    o.background = kBlack;
    const Image image = renderMeshes({{box({0, 0, 0}, 0.5)}}, o).image;

    const double aspect = double(c.width) / c.height;
    const double tanY = std::tan(c.fovDeg * M_PI / 360);
    const double halfAngle = std::min(std::atan(tanY), std::atan(tanY * aspect));
    const double distance = std::sqrt(3.0) / 2 / std::sin(halfAngle) / c.zoom;
    const double ndc = 0.5 / (distance - 0.5) / tanY;  // vertical half-extent of the front face
    const double halfWidth = ndc / aspect * c.width / 2;
    const double halfHeight = ndc * c.height / 2;

    int checked = 0;
    for (int y = 0; y < c.height; ++y) {
      for (int x = 0; x < c.width; ++x) {
        // Signed distance of the pixel centre outside the rectangle (negative inside).
        const double dx = std::abs(x + 0.5 - c.width / 2.0) - halfWidth;
        const double dy = std::abs(y + 0.5 - c.height / 2.0) - halfHeight;
        const double outside = std::max(dx, dy);
        if (std::abs(outside) < 0.01) continue;
        ++checked;
        ASSERT_EQ(isBackground(image, x, y, toBytes(kBlack)), outside > 0)
            << "pixel " << x << "," << y << " is " << outside << " px outside the rectangle";
      }
    }
    EXPECT_GT(checked, c.width * c.height * 9 / 10);
  }
}

// The centroid of the pixels whose colour has exactly the zero channels of `color`.
Eigen::Vector2d centroidOf(const Image& image, const Rgb& color) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      bool match = true;
      for (int c = 0; c < 3; ++c)
        match = match && ((p[c] == 0) == (color[c] == 0));
      if (match) {
        sum += Eigen::Vector2d(x + 0.5, y + 0.5);
        ++count;
      }
    }
  }
  EXPECT_GT(count, 50) << "colour " << color[0] << "," << color[1] << "," << color[2];
  return sum / std::max(count, 1);
}

// A cube on each half axis, each in a colour with its own zero channels,
// some coloured per vertex: where the camera conventions put them.
TEST_P(RenderBackendTest, OrbitCameraFollowsAzimuthAndElevation) {
  const Rgb red{1, 0, 0}, green{0, 1, 0}, blue{0, 0, 1}, magenta{1, 0, 1}, yellow{1, 1, 0},
      cyan{0, 1, 1};
  const std::vector<RenderItem> items = {{box({2, 0, 0}, 0.5, std::vector<Rgb>(8, red))},
                                         {box({-2, 0, 0}, 0.5), green},
                                         {box({0, 2, 0}, 0.5, std::vector<Rgb>(8, blue))},
                                         {box({0, -2, 0}, 0.5), magenta},
                                         {box({0, 0, 2}, 0.5), yellow},
                                         {box({0, 0, -2}, 0.5, std::vector<Rgb>(8, cyan))}};
  auto o = options(GetParam(), 240, 240);
  const double mid = 120;

  o.view = {.azimuthDeg = 0, .elevationDeg = 0};  // from +z: x right, y up
  Image image = renderMeshes(items, o).image;
  EXPECT_GT(centroidOf(image, red).x(), mid + 20);
  EXPECT_LT(centroidOf(image, green).x(), mid - 20);
  EXPECT_LT(centroidOf(image, blue).y(), mid - 20);
  EXPECT_GT(centroidOf(image, magenta).y(), mid + 20);
  EXPECT_NEAR(centroidOf(image, yellow).x(), mid, 1);
  EXPECT_NEAR(centroidOf(image, yellow).y(), mid, 1);

  o.view = {.azimuthDeg = 90, .elevationDeg = 0};  // from +x: -z right, y up
  image = renderMeshes(items, o).image;
  EXPECT_GT(centroidOf(image, cyan).x(), mid + 20);
  EXPECT_LT(centroidOf(image, yellow).x(), mid - 20);
  EXPECT_LT(centroidOf(image, blue).y(), mid - 20);
  EXPECT_NEAR(centroidOf(image, red).x(), mid, 1);

  o.view = {.azimuthDeg = 0, .elevationDeg = 90};  // from +y: x right, -z up
  image = renderMeshes(items, o).image;
  EXPECT_GT(centroidOf(image, red).x(), mid + 20);
  EXPECT_LT(centroidOf(image, cyan).y(), mid - 20);
  EXPECT_GT(centroidOf(image, yellow).y(), mid + 20);
  EXPECT_NEAR(centroidOf(image, blue).x(), mid, 1);
  EXPECT_NEAR(centroidOf(image, blue).y(), mid, 1);
}

TEST_P(RenderBackendTest, VertexColoursShowThroughTheShading) {
  const Rgb red{1, 0, 0}, cyan{0, 1, 1};
  // Two squares side by side facing the camera: red on the left, cyan on the right.
  const std::vector<Eigen::Vector3d> points = {{-1, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-1, 1, 0},
                                               {0, -1, 0},  {1, -1, 0}, {1, 1, 0}, {0, 1, 0}};
  const auto mesh = makeMesh(points, {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}},
                             {red, red, red, red, cyan, cyan, cyan, cyan});
  auto o = options(GetParam(), 200, 100);
  o.view = {.azimuthDeg = 0, .elevationDeg = 0};
  const Image image = renderMeshes({{mesh}}, o).image;
  const std::uint8_t* left = image.pixel(83, 50);
  const std::uint8_t* right = image.pixel(117, 50);
  EXPECT_GT(left[0], 100);
  EXPECT_EQ(left[1], 0);
  EXPECT_EQ(left[2], 0);
  EXPECT_EQ(right[0], 0);
  EXPECT_GT(right[1], 100);
  EXPECT_EQ(right[1], right[2]);
}

TEST_P(RenderBackendTest, UncoveredPixelsHaveTheBackgroundColour) {
  auto o = options(GetParam(), 160, 120);
  o.background = {0.2f, 0.5f, 0.9f};
  const Image image = renderMeshes({{loadMesh("bunny_small.obj")}}, o).image;
  const auto expected = toBytes(o.background);
  EXPECT_EQ(expected, (std::array<std::uint8_t, 3>{51, 128, 230}));
  int background = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      EXPECT_EQ(image.pixel(x, y)[3], 255);
      const bool border = x == 0 || y == 0 || x == image.width - 1 || y == image.height - 1;
      if (border) {
        EXPECT_TRUE(isBackground(image, x, y, expected)) << x << "," << y;
      }
      background += isBackground(image, x, y, expected);
    }
  }
  EXPECT_GT(background, image.width * image.height / 3);
  EXPECT_LT(background, image.width * image.height * 9 / 10);
}

// The bounding rectangle of the covered pixels.
Eigen::AlignedBox2i coveredBox(const Image& image, const std::array<std::uint8_t, 3>& bg) {
  Eigen::AlignedBox2i box;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (!isBackground(image, x, y, bg)) box.extend(Eigen::Vector2i(x, y));
  return box;
}

TEST_P(RenderBackendTest, FramingKeepsTheWholeSceneInside) {
  const std::vector<RenderItem> items = {{loadMesh("bunny_small.obj")}};
  for (auto [width, height] : {std::pair{240, 160}, {160, 240}}) {
    for (auto [azimuth, elevation] :
         {std::pair{0.0, 0.0}, {90.0, 0.0}, {200.0, -60.0}, {-45.0, 89.0}, {30.0, 90.0}}) {
      SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + " az " +
                   std::to_string(azimuth) + " el " + std::to_string(elevation));
      auto o = options(GetParam(), width, height);
      o.view = {.azimuthDeg = azimuth, .elevationDeg = elevation};
      o.background = kBlack;
      const Eigen::AlignedBox2i box = coveredBox(renderMeshes(items, o).image, toBytes(kBlack));
      ASSERT_FALSE(box.isEmpty());
      EXPECT_GT(box.min().minCoeff(), 0);
      EXPECT_LT(box.max().x(), width - 1);
      EXPECT_LT(box.max().y(), height - 1);
      // Fitted, not lost in the middle: the sphere around the box is tight
      // enough that the bunny spans a good part of the narrower side.
      EXPECT_GT(box.sizes().maxCoeff(), 0.4 * std::min(width, height));

      o.view.zoom = 3;
      const Eigen::AlignedBox2i zoomed = coveredBox(renderMeshes(items, o).image, toBytes(kBlack));
      EXPECT_GT(zoomed.sizes().maxCoeff(), 1.5 * box.sizes().maxCoeff());
    }
  }
}

// What a viewport relies on: overlays projected with renderCamera() land on the pixels the
// render covers, rays cast from pixels pass through the points seen there, panning shifts the
// image, and a fixed frame keeps the camera while the items change.
TEST_P(RenderBackendTest, TheCameraProjectsWhatTheImageShows) {
  const Eigen::Vector3d centre(1, 2, 3);
  const std::vector<RenderItem> items = {{box(centre, 0.5)}};
  auto o = options(GetParam(), 320, 240);
  o.view = {.azimuthDeg = 30, .elevationDeg = 20};
  o.background = kBlack;
  const RenderCamera camera = renderCamera(items, o);
  const Image image = renderMeshes(items, o).image;
  const auto projected = camera.project(centre);
  ASSERT_TRUE(projected.has_value());
  EXPECT_NEAR(projected->x(), 160, 1e-9);  // the box centre is what the camera looks at
  EXPECT_NEAR(projected->y(), 120, 1e-9);
  // The corner nearest the eye: covered where projected, and on the ray through that pixel.
  const Eigen::Vector3d corner = centre + 0.5 * Eigen::Vector3d(1, 1, 1);
  const auto window = camera.project(corner);
  ASSERT_TRUE(window.has_value());
  EXPECT_FALSE(isBackground(image, int(window->x() - 2), int(window->y() + 2), toBytes(kBlack)));
  const auto [eye, direction] = camera.ray(window->x(), window->y());
  const Eigen::Vector3d toCorner = corner - eye;
  EXPECT_NEAR((toCorner - toCorner.dot(direction) * direction).norm(), 0, 1e-9);
  EXPECT_NEAR(direction.norm(), 1, 1e-12);

  // Looking further right moves the scene left on the screen.
  o.view.panRight = 0.5;
  EXPECT_LT(renderCamera(items, o).project(centre)->x(), 150);
  const Eigen::AlignedBox2i panned = coveredBox(renderMeshes(items, o).image, toBytes(kBlack));
  EXPECT_LT(panned.center().x(), coveredBox(image, toBytes(kBlack)).center().x() - 10);
  o.view.panRight = 0;

  // A fixed frame: another item far away leaves where everything projects (the depth range
  // grows to hold it) and is still drawn.
  o.frame = RenderFrame{{centre.x(), centre.y(), centre.z()}, 1.0};
  const RenderCamera framed = renderCamera(items, o);
  const Eigen::Vector3d far = centre + Eigen::Vector3d(0, 0, -6);
  const std::vector<RenderItem> more = {items[0], {box(far, 0.2)}};
  const RenderCamera withMore = renderCamera(more, o);
  for (const Eigen::Vector3d& p : {centre, corner, far})
    EXPECT_TRUE(withMore.project(p)->head<2>().isApprox(framed.project(p)->head<2>(), 1e-12));
  const auto farPixel = withMore.project(far);
  const Image both = renderMeshes(more, o).image;
  EXPECT_FALSE(isBackground(both, int(farPixel->x()), int(farPixel->y()), toBytes(kBlack)));
  EXPECT_TRUE(isBackground(renderMeshes(items, o).image, int(farPixel->x()), int(farPixel->y()),
                           toBytes(kBlack)));
  o.frame->radius = 0;
  EXPECT_THAT([&] { renderCamera(items, o); }, ::testing::Throws<std::runtime_error>());
}

TEST_P(RenderBackendTest, RenderingIsDeterministic) {
  const std::vector<RenderItem> items = {{loadMesh("bunny_small.obj"), {0.7f, 0.7f, 0.7f}, true}};
  const auto o = options(GetParam(), 300, 200);
  const Image first = renderMeshes(items, o).image;
  const Image second = renderMeshes(items, o).image;
  EXPECT_TRUE(first.rgba == second.rgba);
  EXPECT_EQ(first.contentHash(), second.contentHash());
}

// A Renderer keeps each mesh's geometry between frames: through orbits, a wireframe, a new
// colour, a second item, a fixed frame and a changed mesh, every frame and camera is renderMeshes'
// and renderCamera's, bit for bit.
TEST_P(RenderBackendTest, ARendererDrawsWhatRenderMeshesDrawsFrameAfterFrame) {
  const MeshPtr bunny = loadMesh("bunny_small.obj");
  const MeshPtr cube = box({0.05, 0.1, 0}, 0.03, std::vector<Rgb>(8, Rgb{0.9f, 0.2f, 0.1f}));
  Renderer renderer;
  auto o = options(GetParam(), 160, 120);
  std::vector<RenderItem> items = {{bunny, {0.7f, 0.7f, 0.7f}, false}};
  const auto check = [&](const std::string& what) {
    const RenderCamera kept = renderer.camera(items, o);
    const RenderCamera fresh = renderCamera(items, o);
    EXPECT_TRUE(kept.viewProjection == fresh.viewProjection && kept.eye == fresh.eye) << what;
    EXPECT_TRUE(renderer.render(items, o).image.rgba == renderMeshes(items, o).image.rgba) << what;
  };
  for (double azimuth : {0.0, 40.0, 170.0, -95.0}) {
    o.view.azimuthDeg = azimuth;
    check("azimuth " + std::to_string(azimuth));
  }
  items[0].wireframe = true;
  check("wireframe");
  items[0].color = {0.2f, 0.6f, 0.9f};
  check("another colour");
  items.push_back({cube});
  check("a second item, which moves the framed centre");
  o.frame = RenderFrame{{0.05, 0.1, 0}, 0.05};
  check("a fixed frame");
  o.view.elevationDeg = -60;
  check("from below");
  items[0].mesh = loadMesh("bunny_small.obj");  // equal content, another value
  check("another mesh value");
  items.erase(items.begin());
  check("the first item gone");
}

TEST_P(RenderBackendTest, GeometryPreparedAheadIsUsedWhereItFitsAndChangesNoImage) {
  const MeshPtr bunny = loadMesh("bunny_small.obj");
  const MeshPtr cube = box({0.05, 0.1, 0}, 0.03, std::vector<Rgb>(8, Rgb{0.9f, 0.2f, 0.1f}));
  auto o = options(GetParam(), 160, 120);
  const RenderItem item{bunny, {0.7f, 0.7f, 0.7f}, false};
  const auto fresh = [&](const std::vector<RenderItem>& items) {
    return renderMeshes(items, o).image.rgba;
  };

  // Around the mesh's own centre, as a render of it alone frames it: no build at the frame.
  Renderer renderer;
  std::optional<Renderer::Prepared> prepared;
  std::thread([&] { prepared = Renderer::prepare(item, std::nullopt); }).join();
  ASSERT_TRUE(*prepared);
  renderer.keep(*prepared);
  EXPECT_EQ(renderer.render({item}, o).image.rgba, fresh({item}));
  EXPECT_EQ(renderer.geometryBuilds(), 0u);

  // Around a frame's centre.
  o.frame = RenderFrame{{0.01, 0.1, 0.02}, 0.08};
  renderer.keep(Renderer::prepare(item, o.frame));
  EXPECT_EQ(renderer.render({item}, o).image.rgba, fresh({item}));
  EXPECT_EQ(renderer.geometryBuilds(), 0u);

  // Where it does not fit (another centre, another colour), the frame builds its own.
  renderer.keep(Renderer::prepare(item, RenderFrame{{0, 0, 0}, 1}));
  EXPECT_EQ(renderer.render({item}, o).image.rgba, fresh({item}));
  EXPECT_EQ(renderer.geometryBuilds(), 1u);
  RenderItem grey = item;
  grey.color = {0.5f, 0.5f, 0.5f};
  renderer.keep(Renderer::prepare(item, o.frame));
  EXPECT_EQ(renderer.render({grey}, o).image.rgba, fresh({grey}));
  EXPECT_EQ(renderer.geometryBuilds(), 2u);

  // A prepared mesh that is not drawn changes nothing; one beside another item is used.
  renderer.keep(Renderer::prepare({cube}, o.frame));
  EXPECT_EQ(renderer.render({grey}, o).image.rgba, fresh({grey}));
  renderer.keep(Renderer::prepare({cube}, o.frame));
  EXPECT_EQ(renderer.render({grey, {cube}}, o).image.rgba, fresh({grey, {cube}}));
  EXPECT_EQ(renderer.geometryBuilds(), 2u);

  // What a render refuses is not prepared; keeping nothing is allowed.
  EXPECT_FALSE(Renderer::prepare({std::make_shared<const Mesh>()}, std::nullopt));
  EXPECT_FALSE(Renderer::prepare({nullptr}, std::nullopt));
  renderer.keep(nullptr);
}

TEST_P(RenderBackendTest, BothSidesAreLitAlike) {
  auto o = options(GetParam(), 120, 120);
  o.view = {.azimuthDeg = 10, .elevationDeg = 15};
  const Image front = renderMeshes({{square(1, false)}}, o).image;
  const Image back = renderMeshes({{square(1, true)}}, o).image;
  const Agreement agreement = compare(front, back, toBytes({1, 1, 1}), 1);
  EXPECT_GE(agreement.closeFraction, 0.999);
  EXPECT_EQ(agreement.coverageDifferences, 0);
}

TEST_P(RenderBackendTest, WireframeDarkensTriangleEdgesOnly) {
  // Head-on, the square overfills the image, its diagonal through the centre.
  auto o = options(GetParam(), 101, 101);
  o.view = {.azimuthDeg = 0, .elevationDeg = 0, .zoom = 1.5};
  const Image shaded = renderMeshes({{square(1), {0.8f, 0.8f, 0.8f}, false}}, o).image;
  const Image wired = renderMeshes({{square(1), {0.8f, 0.8f, 0.8f}, true}}, o).image;

  const std::uint8_t centreGrey = shaded.pixel(50, 50)[0];
  EXPECT_GT(centreGrey, 120);
  // A flat square under directional lights is evenly lit.
  EXPECT_EQ(shaded.pixel(40, 40)[0], centreGrey);
  EXPECT_EQ(shaded.pixel(60, 60)[0], centreGrey);
  // On the diagonal (the edge both triangles share, bottom left to top right): dark.
  EXPECT_LT(wired.pixel(50, 50)[0], 40);
  EXPECT_LT(wired.pixel(30, 70)[0], 40);
  // Fourteen pixels away from every edge: untouched.
  EXPECT_EQ(wired.pixel(40, 40)[0], centreGrey);
  EXPECT_EQ(wired.pixel(60, 60)[0], centreGrey);
}

TEST_P(RenderBackendTest, TheFirstOfCoincidentSurfacesStaysInFront) {
  auto o = options(GetParam(), 64, 64);
  const auto first = renderMeshes({{square(1), {1, 0, 0}}, {square(1), {0, 1, 0}}}, o).image;
  const std::uint8_t* centre = first.pixel(32, 32);
  EXPECT_GT(centre[0], 0);
  EXPECT_EQ(centre[1], 0);
}

// Edges through pixel centres: the square's outline and the line between its
// red and green halves are placed exactly on centres (the zoom is solved for
// that from the framing rule), so the top-left rule decides every edge pixel.
TEST(RenderTest, CpuRasterizerFollowsTheTopLeftFillRule) {
  const int size = 61, centre = 30, half = 20;
  const double halfFov = 35 * M_PI / 360;
  const double zoom = half / (std::cos(halfFov) / std::sqrt(2.0) * size / 2);
  const Rgb red{1, 0, 0}, green{0, 1, 0};
  const std::vector<Eigen::Vector3d> points = {{-1, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-1, 1, 0},
                                               {0, -1, 0},  {1, -1, 0}, {1, 1, 0}, {0, 1, 0}};
  const auto mesh = makeMesh(points, {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}},
                             {red, red, red, red, green, green, green, green});
  auto o = options(RenderBackend::Cpu, size, size);
  o.view = {.azimuthDeg = 0, .elevationDeg = 0, .fovDeg = 35, .zoom = zoom};
  o.background = kBlack;
  const Image image = renderMeshes({{mesh}}, o).image;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      // Top and left edges are in, bottom and right edges out; the shared
      // edge is the green half's left edge.
      const bool inside =
          x >= centre - half && x < centre + half && y >= centre - half && y < centre + half;
      const std::uint8_t* p = image.pixel(x, y);
      ASSERT_EQ(p[0] > 0, inside && x < centre) << x << "," << y;
      ASSERT_EQ(p[1] > 0, inside && x >= centre) << x << "," << y;
    }
  }
}

void expectRenderError(const std::vector<RenderItem>& items, const RenderOptions& o,
                       const std::string& message) {
  try {
    renderMeshes(items, o);
    ADD_FAILURE() << "no exception; expected one saying '" << message << "'";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr(message));
  }
}

TEST_P(RenderBackendTest, BadInputsThrowClearMessages) {
  const auto cube = box({0, 0, 0}, 1);
  const std::vector<RenderItem> items = {{cube}};
  expectRenderError(items, options(GetParam(), 0, 10), "width 0 is outside 1..8192");
  expectRenderError(items, options(GetParam(), 10, 8193), "height 8193 is outside 1..8192");
  auto o = options(GetParam());
  o.view.fovDeg = 0;
  expectRenderError(items, o, "fovDeg");
  o = options(GetParam());
  o.view.zoom = -1;
  expectRenderError(items, o, "zoom");

  o = options(GetParam());
  expectRenderError({}, o, "nothing to draw");
  expectRenderError({{cube}, {nullptr}}, o, "item 1 has no mesh");
  TriMesh pointsOnly;
  pointsOnly.add_vertex({0, 0, 0});
  expectRenderError({{cube}, {std::make_shared<const Mesh>(pointsOnly)}}, o,
                    "item 1: the mesh has no faces");
  const double nan = std::nan("");
  expectRenderError({{makeMesh({{0, 0, 0}, {1, 0, 0}, {0, nan, 0}}, {{0, 1, 2}})}}, o,
                    "item 0: vertex 2 has a non-finite coordinate");
  expectRenderError({{makeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, {{1, 0, 0}})}}, o,
                    "item 0: 1 vertex colours for 3 vertices");
}

TEST(RenderTest, ForcedVulkanRunsOnTheSharedDevice) {
  SKIP_WITHOUT_VULKAN();
  const gpu::VulkanContext* context = gpu::VulkanContext::shared();
  const RenderResult result =
      renderMeshes({{loadMesh("bunny_small.obj")}}, options(RenderBackend::Vulkan, 64, 48));
  EXPECT_EQ(result.backend, "vulkan");
  EXPECT_EQ(result.device, context->deviceName());
  EXPECT_EQ(result.image.width, 64);
  EXPECT_EQ(result.image.height, 48);
  // Auto draws on the CPU rasterizer, a device or not.
  EXPECT_EQ(renderMeshes({{box({0, 0, 0}, 1)}}, options(RenderBackend::Auto, 8, 8)).backend, "cpu");
}

TEST(RenderTest, ConcurrentVulkanRendersMatchASerialOne) {
  SKIP_WITHOUT_VULKAN();
  const std::vector<RenderItem> items = {{loadMesh("bunny_small.obj")}};
  const auto o = options(RenderBackend::Vulkan, 160, 120);
  const Image reference = renderMeshes(items, o).image;
  std::vector<Image> images(4);
  std::vector<std::thread> threads;
  for (Image& image : images)
    threads.emplace_back([&] { image = renderMeshes(items, o).image; });
  for (std::thread& thread : threads)
    thread.join();
  for (const Image& image : images)
    EXPECT_TRUE(image.rgba == reference.rgba);
}

TEST(VulkanContextTest, SharedContextIsOneObjectAcrossThreads) {
  SKIP_WITHOUT_VULKAN();
  std::vector<gpu::VulkanContext*> seen(8);
  std::vector<std::thread> threads;
  for (auto& slot : seen)
    threads.emplace_back([&slot] { slot = gpu::VulkanContext::shared(); });
  for (auto& thread : threads)
    thread.join();
  for (auto* context : seen)
    EXPECT_EQ(context, gpu::VulkanContext::shared());
  EXPECT_TRUE(gpu::VulkanContext::unavailableReason().empty());
}

// Buffers, images and submissions are exercised by every Vulkan render above;
// this covers the refusal that no render reaches.
TEST(VulkanContextTest, MemoryTypeLookupRefusesWhatNoTypeOffers) {
  SKIP_WITHOUT_VULKAN();
  const gpu::VulkanContext& context = *gpu::VulkanContext::shared();
  try {
    context.memoryType(0, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    ADD_FAILURE() << "memoryType accepted an empty type mask";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("has no memory type with property flags"));
  }
  EXPECT_NO_THROW(context.memoryType(~0u, 0));
}

// In a child process, where the device is forced to one that does not exist.
TEST(RenderDeathTest, WithoutVulkanForcedRendersThrowAndAutoFallsBack) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        ::setenv("GEOBRUSH_VK_DEVICE", "no such device", 1);
        const std::vector<RenderItem> items = {{box({0, 0, 0}, 1)}};
        try {
          renderMeshes(items, options(RenderBackend::Vulkan, 8, 8));
          std::exit(1);
        } catch (const std::runtime_error& error) {
          std::fprintf(stderr, "%s\n", error.what());
        }
        const RenderResult result = renderMeshes(items, options(RenderBackend::Auto, 8, 8));
        std::fprintf(stderr, "auto: %s\n", result.backend.c_str());
        std::exit(gpu::VulkanContext::shared() == nullptr ? 0 : 1);
      },
      ::testing::ExitedWithCode(0),
      "the Vulkan backend is unavailable: GEOBRUSH_VK_DEVICE=no such device: matches no "
      "device.*auto: cpu");
}

TEST(VulkanContextTest, FailedCallsBecomeExceptionsNamingTheCall) {
  EXPECT_NO_THROW(gpu::check(VK_SUCCESS, "vkCreateBuffer"));
  try {
    gpu::check(VK_ERROR_DEVICE_LOST, "vkQueueSubmit");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("vkQueueSubmit failed: VK_ERROR_DEVICE_LOST"));
  }
}

TEST(VulkanContextTest, PickDevicePrefersDiscreteThenIntegratedThenVirtualThenCpu) {
  using gpu::DeviceInfo;
  const DeviceInfo cpu{"llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU, true};
  const DeviceInfo integrated{"Intel(R) UHD Graphics 630", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
                              true};
  const DeviceInfo discrete{"NVIDIA GeForce RTX 3080", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, true};
  const DeviceInfo virtualGpu{"virgl", VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, true};
  DeviceInfo oldDiscrete = discrete;
  oldDiscrete.usable = false;

  EXPECT_EQ(gpu::pickDevice(std::vector{cpu, integrated, discrete}, ""), 2u);
  EXPECT_EQ(gpu::pickDevice(std::vector{cpu, integrated}, ""), 1u);
  EXPECT_EQ(gpu::pickDevice(std::vector{cpu, virtualGpu}, ""), 1u);
  EXPECT_EQ(gpu::pickDevice(std::vector{cpu}, ""), 0u);
  EXPECT_EQ(gpu::pickDevice(std::vector{oldDiscrete, cpu}, ""), 1u);
}

TEST(VulkanContextTest, PickDeviceHonoursTheForcedChoice) {
  using gpu::DeviceInfo;
  const std::vector<DeviceInfo> devices = {
      {"NVIDIA GeForce RTX 3080", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, true},
      {"llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU, true},
      {"Old Radeon", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, false}};
  EXPECT_EQ(gpu::pickDevice(devices, "LLVMpipe"), 1u);
  EXPECT_EQ(gpu::pickDevice(devices, "1"), 1u);
  EXPECT_EQ(gpu::pickDevice(devices, "0"), 0u);
  const auto expectError = [&](std::string_view forced, const std::string& message) {
    try {
      gpu::pickDevice(devices, forced);
      ADD_FAILURE() << "GEOBRUSH_VK_DEVICE=" << forced << " was accepted";
    } catch (const std::runtime_error& error) {
      EXPECT_THAT(error.what(), HasSubstr(message));
    }
  };
  expectError("7", "no device with that index");
  expectError("intel", "matches no device (found 0: NVIDIA GeForce RTX 3080 [discrete GPU], 1:");
  expectError("radeon", "lacks Vulkan 1.2 or a graphics+compute queue");
  EXPECT_THROW(gpu::pickDevice(std::vector<DeviceInfo>{}, ""), std::runtime_error);
}

Image randomImage(int width, int height) {
  std::mt19937 random(1234);
  Image image(width, height);
  for (auto& byte : image.rgba)
    byte = std::uint8_t(random());
  return image;
}

TEST(ImageTest, PngRoundTripIsLosslessAndLeavesNoTemporaryFile) {
  const auto dir = test::tempDir("render-png");
  const Image image = randomImage(37, 23);
  const auto path = dir / "random.png";
  writePng(image, path);
  writePng(image, path);  // replacing an existing file works too
  const Image back = readPng(path);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_TRUE(back.rgba == image.rgba);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
}

TEST(ImageTest, PngErrorsNameThePath) {
  const auto dir = test::tempDir("render-png-errors");
  const auto missingFolder = dir / "no" / "such" / "folder" / "x.png";
  try {
    writePng(randomImage(4, 4), missingFolder);
    ADD_FAILURE() << "wrote into a missing folder";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr(missingFolder.string()));
  }
  EXPECT_FALSE(std::filesystem::exists(missingFolder.parent_path()));

  const auto notPng = dir / "text.png";
  std::ofstream(notPng) << "not an image";
  try {
    readPng(notPng);
    ADD_FAILURE() << "decoded a text file";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr(notPng.string()));
  }
  EXPECT_THROW(writePng(Image(), dir / "empty.png"), std::runtime_error);
}

// An existing output must be a regular file or a link to one (written through, the link kept):
// a FIFO, a socket, a device or a folder is refused, not replaced by the PNG.
TEST(ImageTest, PngReplacesOnlyARegularFileOrTheFileALinkNames) {
  const auto dir = test::tempDir("render-png-special");
  const Image image = randomImage(5, 3);
  const auto fifo = dir / "fifo.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::filesystem::create_directory(dir / "folder.png");
  for (const char* name : {"fifo.png", "folder.png"}) {
    try {
      writePng(image, dir / name);
      ADD_FAILURE() << "replaced " << name;
    } catch (const std::runtime_error& error) {
      EXPECT_THAT(error.what(), HasSubstr(test::quoted(dir / name) + ": is a "));
    }
  }
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_TRUE(std::filesystem::is_directory(dir / "folder.png"));

  std::filesystem::create_directory(dir / "real");
  std::ofstream(dir / "real" / "target.png") << "old";
  std::filesystem::create_symlink("real/target.png", dir / "link.png");
  writePng(image, dir / "link.png");
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "link.png"));
  EXPECT_TRUE(readPng(dir / "real" / "target.png").rgba == image.rgba);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "real"), {}), 1);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 4);

  // A link to a link to a FIFO, and a loop of links.
  std::filesystem::create_symlink("fifo.png", dir / "hop1.png");
  std::filesystem::create_symlink("hop1.png", dir / "hop2.png");
  EXPECT_THROW(writePng(image, dir / "hop2.png"), std::runtime_error);
  std::filesystem::create_symlink("loop_b.png", dir / "loop_a.png");
  std::filesystem::create_symlink("loop_a.png", dir / "loop_b.png");
  try {
    writePng(image, dir / "loop_a.png");
    ADD_FAILURE() << "wrote through a loop of links";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("too many levels of symbolic links"));
  }
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
}

TEST(ImageTest, HashFollowsContentAndShape) {
  const Image a = randomImage(4, 4);
  Image b = a;
  EXPECT_EQ(a.contentHash(), b.contentHash());
  b.pixel(3, 3)[2] ^= 1;
  EXPECT_NE(a.contentHash(), b.contentHash());
  Image reshaped = a;
  reshaped.width = 2;
  reshaped.height = 8;
  EXPECT_NE(a.contentHash(), reshaped.contentHash());
  EXPECT_EQ(a.summary(), "image: 4x4 RGBA8");
  EXPECT_EQ(a.typeId(), "geobrush.Image");
}

}  // namespace
}  // namespace geobrush
