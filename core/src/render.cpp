// renderMeshes(): input checks, camera framing, lighting and the choice of
// backend. Shading model (shared with shaders/mesh.frag and render_cpu.cpp):
// colour × (ambient + Lambert from a headlight + Lambert from a soft fill
// light above and to the left), two-sided, smooth area-weighted normals.
// Colours reach the image as they are, with no sRGB curve: as in common mesh
// viewers, this keeps the Lambert fall-off visible, and a colour c is stored
// as round(255 c). Wireframe edges darken pixels by their exact distance to
// the triangle's edge lines, computed here once in window coordinates: unlike
// interpolated barycentrics, that does not depend on how a driver clips.
// No multisampling in either backend, so the two agree pixel for pixel away
// from edges.
#include "geobrush/render.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "geobrush/gpu/vulkan_context.hpp"
#include "render_scene.hpp"

namespace geobrush {
namespace detail {
namespace {

constexpr int kMaxSize = 8192;
constexpr float kAmbient = 0.08f;
constexpr float kHeadlight = 0.62f;
constexpr float kFillLight = 0.35f;
constexpr float kEdgeGrey = 0.05f;

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error("renderMeshes: " + what);
}

bool finite(const Rgb& color) {
  return std::isfinite(color[0]) && std::isfinite(color[1]) && std::isfinite(color[2]);
}

void checkOptions(const RenderOptions& options) {
  for (auto [name, size] : {std::pair{"width", options.width}, {"height", options.height}}) {
    if (size < 1 || size > kMaxSize)
      fail(std::string(name) + " " + std::to_string(size) + " is outside 1.." +
           std::to_string(kMaxSize));
  }
  const RenderView& view = options.view;
  if (!(view.fovDeg > 0 && view.fovDeg < 180))
    fail("fovDeg " + std::to_string(view.fovDeg) + " is outside (0, 180)");
  if (!(view.zoom > 0) || !std::isfinite(view.zoom))
    fail("zoom " + std::to_string(view.zoom) + " is not a positive number");
  if (!std::isfinite(view.azimuthDeg) || !std::isfinite(view.elevationDeg))
    fail("azimuthDeg and elevationDeg must be finite");
  if (!std::isfinite(view.panRight) || !std::isfinite(view.panUp))
    fail("panRight and panUp must be finite");
  if (options.frame) {
    const RenderFrame& frame = *options.frame;
    if (!std::isfinite(frame.center[0]) || !std::isfinite(frame.center[1]) ||
        !std::isfinite(frame.center[2]) || !(frame.radius > 0) || !std::isfinite(frame.radius))
      fail("the frame needs a finite centre and a positive radius");
  }
  if (!finite(options.background)) fail("the background colour is not finite");
}

void checkItem(const RenderItem& item, std::size_t index) {
  const std::string name = "item " + std::to_string(index);
  if (!item.mesh) fail(name + " has no mesh");
  const TriMesh& surface = item.mesh->surface;
  if (surface.faces().begin() == surface.faces().end()) fail(name + ": the mesh has no faces");
  if (!finite(item.color)) fail(name + ": the colour is not finite");
  const auto& colors = item.mesh->vertexColors;
  if (!colors.empty() && colors.size() != surface.n_vertices())
    fail(name + ": " + std::to_string(colors.size()) + " vertex colours for " +
         std::to_string(surface.n_vertices()) + " vertices");
  for (auto v : surface.vertices()) {
    if (!toEigen(surface.point(v)).allFinite())
      fail(name + ": vertex " + std::to_string(v.idx()) + " has a non-finite coordinate");
    if (!colors.empty() && !finite(colors[v.idx()]))
      fail(name + ": the colour of vertex " + std::to_string(v.idx()) + " is not finite");
  }
}

Eigen::AlignedBox3d boundingBox(const std::vector<RenderItem>& items) {
  Eigen::AlignedBox3d box;
  for (const RenderItem& item : items)
    for (auto v : item.mesh->surface.vertices())
      box.extend(toEigen(item.mesh->surface.point(v)));
  return box;
}

// An orbit camera in coordinates relative to the centre of the bounding box.
struct Camera {
  Eigen::Vector3d eye, right, up, back;
  Eigen::Matrix4d viewProjection;
};

// Distance at which a sphere of `radius` fits both fields of view, divided by
// the zoom; the azimuth turns from +z towards +x, the elevation lifts off xz.
// The near and far planes hold a sphere of `clipRadius` (>= radius) around the
// same centre, so that what lies outside a fixed frame is still drawn.
double fittedDistance(double radius, const RenderView& view, int width, int height) {
  const double halfFovY = view.fovDeg * M_PI / 360;
  const double halfFovX = std::atan(std::tan(halfFovY) * width / height);
  return radius / std::sin(std::min(halfFovX, halfFovY)) / view.zoom;
}

Camera fitCamera(double radius, double clipRadius, const RenderView& view, int width, int height) {
  const double halfFovY = view.fovDeg * M_PI / 360;
  const double distance = fittedDistance(radius, view, width, height);
  const double azimuth = view.azimuthDeg * M_PI / 180;
  const double elevation = view.elevationDeg * M_PI / 180;

  Camera camera;
  camera.back = {std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                 std::cos(elevation) * std::cos(azimuth)};
  // Taken from the azimuth alone, the right vector stays defined straight
  // above and below the scene.
  camera.right = {std::cos(azimuth), 0, -std::sin(azimuth)};
  camera.up = camera.back.cross(camera.right);
  const Eigen::Vector3d lookAt = radius * (view.panRight * camera.right + view.panUp * camera.up);
  camera.eye = lookAt + distance * camera.back;

  Eigen::Matrix4d viewMatrix = Eigen::Matrix4d::Identity();
  viewMatrix.block<1, 3>(0, 0) = camera.right.transpose();
  viewMatrix.block<1, 3>(1, 0) = camera.up.transpose();
  viewMatrix.block<1, 3>(2, 0) = camera.back.transpose();
  viewMatrix.block<3, 1>(0, 3) = -viewMatrix.block<3, 3>(0, 0) * camera.eye;

  // Margins keep the sphere's extreme points off the clipping planes; the
  // near plane stays positive when zooming puts the eye inside the sphere.
  // Panning moves the eye across the view axis only, so the depths stay.
  const double far = distance + 1.01 * clipRadius;
  const double near = std::max(distance - 1.01 * clipRadius, 1e-3 * far);
  const double focal = 1 / std::tan(halfFovY);
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = focal * height / width;
  projection(1, 1) = -focal;  // Vulkan's y points down
  projection(2, 2) = far / (near - far);
  projection(2, 3) = near * far / (near - far);
  projection(3, 2) = -1;
  camera.viewProjection = projection * viewMatrix;
  return camera;
}

// What the camera frames: the fixed frame of the options, else the bounding box of the items;
// and the radius of the sphere around the same centre that holds everything drawn.
struct Framing {
  Eigen::Vector3d center;
  double radius = 0;
  double clipRadius = 0;
};

Framing frameItems(const std::vector<RenderItem>& items, const RenderOptions& options) {
  const Eigen::AlignedBox3d box = boundingBox(items);
  const double boxRadius = 0.5 * box.diagonal().norm();
  Framing framing{box.center(), boxRadius, boxRadius};
  if (options.frame) {
    framing.center = Eigen::Vector3d(options.frame->center.data());
    framing.radius = options.frame->radius;
    framing.clipRadius =
        std::max(framing.radius, (box.center() - framing.center).norm() + boxRadius);
  }
  if (!(framing.radius > 0)) fail("all points coincide, so there is nothing to see");
  return framing;
}

// The checks and the camera that every render and renderCamera() share.
std::pair<Framing, Camera> prepareCamera(const std::vector<RenderItem>& items,
                                         const RenderOptions& options) {
  checkOptions(options);
  if (items.empty()) fail("there is nothing to draw (no items)");
  for (std::size_t i = 0; i < items.size(); ++i)
    checkItem(items[i], i);
  const Framing framing = frameItems(items, options);
  return {framing, fitCamera(framing.radius, framing.clipRadius, options.view, options.width,
                             options.height)};
}

std::array<float, 3> toFloats(const Eigen::Vector3d& v) {
  return {float(v.x()), float(v.y()), float(v.z())};
}

// Sum of the face normals around each vertex, each as long as twice the
// face's area: area weighting without a separate area term.
std::vector<Eigen::Vector3d> vertexNormals(const TriMesh& surface) {
  std::vector<Eigen::Vector3d> normals(surface.n_vertices(), Eigen::Vector3d::Zero());
  for (auto f : surface.faces()) {
    auto h = surface.halfedge_handle(f);
    const auto v0 = surface.from_vertex_handle(h);
    const auto v1 = surface.to_vertex_handle(h);
    const auto v2 = surface.to_vertex_handle(surface.next_halfedge_handle(h));
    const Eigen::Vector3d p0 = toEigen(surface.point(v0));
    const Eigen::Vector3d n =
        (toEigen(surface.point(v1)) - p0).cross(toEigen(surface.point(v2)) - p0);
    for (auto v : {v0, v1, v2})
      normals[v.idx()] += n;
  }
  return normals;
}

// Homogeneous window coordinates (pixels, y down) of each corner; the line
// through two of them is their cross product, even for a corner behind the eye.
std::array<std::array<float, 3>, 3> edgeLines(const std::array<Eigen::Vector3d, 3>& points,
                                              const Camera& camera, int width, int height) {
  std::array<Eigen::Vector3d, 3> window;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector4d clip = camera.viewProjection * points[k].homogeneous();
    window[k] = {0.5 * (clip.x() + clip.w()) * width, 0.5 * (clip.y() + clip.w()) * height,
                 clip.w()};
  }
  std::array<std::array<float, 3>, 3> lines;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d line = window[(k + 1) % 3].cross(window[(k + 2) % 3]);
    // An edge seen end-on gives a zero line, but its triangle covers no pixel.
    line /= std::max(line.head<2>().norm(), std::numeric_limits<double>::min());
    lines[k] = toFloats(line);
  }
  return lines;
}

void appendTriangles(const RenderItem& item, const Eigen::Vector3d& centre, const Camera& camera,
                     int width, int height, std::vector<SceneVertex>& out) {
  const TriMesh& surface = item.mesh->surface;
  const auto& colors = item.mesh->vertexColors;
  const std::vector<Eigen::Vector3d> normals = vertexNormals(surface);
  const float wire = item.wireframe ? 1.0f : 0.0f;
  for (auto f : surface.faces()) {
    std::array<TriMesh::VertexHandle, 3> corners;
    std::array<Eigen::Vector3d, 3> points;
    int k = 0;
    for (auto v : surface.fv_range(f)) {
      corners[k] = v;
      points[k++] = toEigen(surface.point(v)) - centre;
    }
    const Eigen::Vector3d faceNormal = (points[1] - points[0]).cross(points[2] - points[0]);
    // Two-sided lighting: a triangle seen from behind is lit as its other side.
    const double side = faceNormal.dot(camera.eye - points[0]) < 0 ? -1 : 1;
    // Only a wireframe reads the edge lines (weighted by 0 elsewhere).
    const auto lines = item.wireframe ? edgeLines(points, camera, width, height)
                                      : std::array<std::array<float, 3>, 3>{};
    for (k = 0; k < 3; ++k) {
      // Where degenerate faces leave no normal: the face's own, else the view direction.
      Eigen::Vector3d normal = normals[corners[k].idx()];
      if (normal.squaredNorm() == 0) normal = faceNormal;
      normal = normal.squaredNorm() > 0 ? Eigen::Vector3d(side * normal.normalized()) : camera.back;
      SceneVertex vertex;
      vertex.position = toFloats(points[k]);
      vertex.normal = toFloats(normal);
      vertex.color = colors.empty() ? item.color : colors[corners[k].idx()];
      vertex.edgeLines = lines;
      vertex.wireframe = wire;
      out.push_back(vertex);
    }
  }
}

ShadingConstants shadingConstants(const Camera& camera) {
  ShadingConstants constants;
  Eigen::Map<Eigen::Matrix4f>(constants.viewProjection.data()) =
      camera.viewProjection.cast<float>();
  const Eigen::Vector3d fill =
      (-0.6 * camera.right + 0.7 * camera.up + 0.2 * camera.back).normalized();
  const auto head = toFloats(camera.back);
  const auto fillDir = toFloats(fill);
  constants.headlight = {head[0], head[1], head[2], kHeadlight};
  constants.fillLight = {fillDir[0], fillDir[1], fillDir[2], kFillLight};
  constants.material = {kAmbient, kEdgeGrey, 0, 0};
  return constants;
}

}  // namespace

std::uint8_t toUnorm8(float value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

Scene prepareScene(const std::vector<RenderItem>& items, const RenderOptions& options) {
  const auto [framing, camera] = prepareCamera(items, options);
  Scene scene;
  scene.width = options.width;
  scene.height = options.height;
  // Reserved whole: grown by doubling, a large mesh's corners would be copied several times.
  std::size_t corners = 0;
  for (const RenderItem& item : items)
    corners += 3 * item.mesh->surface.n_faces();
  scene.vertices.reserve(corners);
  for (const RenderItem& item : items)
    appendTriangles(item, framing.center, camera, scene.width, scene.height, scene.vertices);
  scene.constants = shadingConstants(camera);
  for (int c = 0; c < 3; ++c)
    scene.background[c] = toUnorm8(options.background[c]);
  scene.background[3] = 255;
  return scene;
}

}  // namespace detail

double framedRadiiPerPixel(const RenderView& view, int width, int height) {
  // The view's height at the fitted distance of a unit sphere, over its pixels.
  const double distance = detail::fittedDistance(1, view, width, height);
  return 2 * distance * std::tan(view.fovDeg * M_PI / 360) / height;
}

RenderCamera renderCamera(const std::vector<RenderItem>& items, const RenderOptions& options) {
  const auto [framing, camera] = detail::prepareCamera(items, options);
  // The scene is drawn relative to the framed centre (float precision); the public camera
  // takes world points.
  Eigen::Matrix4d toCentre = Eigen::Matrix4d::Identity();
  toCentre.block<3, 1>(0, 3) = -framing.center;
  return {camera.viewProjection * toCentre, camera.eye + framing.center, options.width,
          options.height};
}

std::optional<Eigen::Vector3d> RenderCamera::project(const Eigen::Vector3d& point) const {
  const Eigen::Vector4d clip = viewProjection * point.homogeneous();
  if (!(clip.w() > 0)) return std::nullopt;
  return Eigen::Vector3d(0.5 * (clip.x() / clip.w() + 1) * width,
                         0.5 * (clip.y() / clip.w() + 1) * height, clip.z() / clip.w());
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> RenderCamera::ray(double x, double y) const {
  // The window position back to normalized device coordinates, then through the inverse to a
  // point on the near plane; the ray runs from the eye through it.
  const Eigen::Vector4d ndc(2 * x / width - 1, 2 * y / height - 1, 0, 1);
  const Eigen::Vector4d world = viewProjection.inverse() * ndc;
  const Eigen::Vector3d onNear = world.head<3>() / world.w();
  return {eye, (onNear - eye).normalized()};
}

RenderResult renderMeshes(const std::vector<RenderItem>& items, const RenderOptions& options) {
  const detail::Scene scene = detail::prepareScene(items, options);
  gpu::VulkanContext* context =
      options.backend == RenderBackend::Cpu ? nullptr : gpu::VulkanContext::shared();
  if (options.backend == RenderBackend::Vulkan && !context)
    throw std::runtime_error("renderMeshes: the Vulkan backend is unavailable: " +
                             gpu::VulkanContext::unavailableReason());
  // Auto falls back to the CPU twin; the result names the backend that drew.
  if (context) {
    try {
      return {detail::renderVulkan(scene, *context), "vulkan", context->deviceName()};
    } catch (const std::exception&) {
      if (options.backend == RenderBackend::Vulkan) throw;
    }
  }
  return {detail::renderCpu(scene), "cpu", "cpu rasterizer"};
}

}  // namespace geobrush
