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
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "geobrush/gpu/vulkan_context.hpp"
#include "geobrush/parallel.hpp"
#include "render_scene.hpp"

namespace geobrush {

// What a render keeps of a mesh it has checked, whatever the camera: its bounding box, and its
// geometry around the last centre it was drawn about.
struct Renderer::KeptMesh {
  MeshPtr mesh;  // held: a value is never changed while it is shared
  Eigen::AlignedBox3d box;
  std::shared_ptr<const detail::SceneMesh> geometry;
};

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

Eigen::AlignedBox3d meshBox(const TriMesh& surface) {
  Eigen::AlignedBox3d box;
  for (auto v : surface.vertices())
    box.extend(toEigen(surface.point(v)));
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

Framing frameItems(const std::vector<Eigen::AlignedBox3d>& boxes, const RenderOptions& options) {
  Eigen::AlignedBox3d box;
  for (const Eigen::AlignedBox3d& itemBox : boxes)
    box.extend(itemBox);
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

// A new kept entry: the item checked (throws as renderMeshes does), its box, no geometry yet.
Renderer::KeptMesh checkedEntry(const RenderItem& item, std::size_t index) {
  checkItem(item, index);
  return {item.mesh, meshBox(item.mesh->surface), nullptr};
}

// The checks and the camera that every render and camera share, for items whose meshes `kept`
// holds checked (one entry per item, in order; a new one where the mesh was not kept).
std::pair<Framing, Camera> prepareCamera(const std::vector<RenderItem>& items,
                                         const RenderOptions& options,
                                         std::vector<Renderer::KeptMesh>& kept) {
  checkOptions(options);
  if (items.empty()) fail("there is nothing to draw (no items)");
  std::vector<Renderer::KeptMesh> current;
  for (std::size_t i = 0; i < items.size(); ++i) {
    // The same item's entry first: one mesh may be drawn twice, in two colours.
    auto same = i < kept.size() && kept[i].mesh == items[i].mesh ? kept.begin() + std::ptrdiff_t(i)
                                                                 : kept.end();
    if (same == kept.end())
      same = std::find_if(kept.begin(), kept.end(), [&](const Renderer::KeptMesh& k) {
        return items[i].mesh && k.mesh == items[i].mesh;
      });
    if (same != kept.end()) {
      current.push_back(*same);
      continue;
    }
    current.push_back(checkedEntry(items[i], i));
  }
  kept = std::move(current);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const Renderer::KeptMesh& k : kept)
    boxes.push_back(k.box);
  const Framing framing = frameItems(boxes, options);
  return {framing, fitCamera(framing.radius, framing.clipRadius, options.view, options.width,
                             options.height)};
}

std::array<float, 3> toFloats(const Eigen::Vector3d& v) {
  return {float(v.x()), float(v.y()), float(v.z())};
}

// The unit vector along v in float; zero where v has no length.
std::array<float, 3> unitOrZero(const Eigen::Vector3d& v) {
  return v.squaredNorm() > 0 ? toFloats(v.normalized()) : std::array<float, 3>{};
}

constexpr std::size_t kBlock = 8192;  // vertices or faces per block of a parallel loop

// Each face's corners, in the mesh's face order; a face's vertex loop starts at the head of its
// halfedge.
std::vector<std::array<int, 3>> faceCorners(const TriMesh& surface) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(surface.n_faces());
  for (auto f : surface.faces()) {
    std::array<int, 3> corners;
    int k = 0;
    for (auto v : surface.fv_range(f))
      corners[std::size_t(k++)] = v.idx();
    faces.push_back(corners);
  }
  return faces;
}

// Sum of the face normals around each vertex, each as long as twice the face's area (area
// weighting without a separate area term), from the mesh's own coordinates. Each vertex adds its
// faces in the mesh's face order, so the sums are the same on any number of threads.
std::vector<Eigen::Vector3d> vertexNormals(const TriMesh& surface,
                                           const std::vector<std::array<int, 3>>& faces) {
  const std::size_t vertices = surface.n_vertices();
  // The faces around each vertex, ascending: a counting sort of the corners by vertex.
  std::vector<std::size_t> start(vertices + 1, 0);
  for (const auto& face : faces)
    for (int v : face)
      ++start[std::size_t(v) + 1];
  for (std::size_t v = 0; v < vertices; ++v)
    start[v + 1] += start[v];
  std::vector<std::uint32_t> around(start.back());
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int v : faces[f])
      around[next[std::size_t(v)]++] = std::uint32_t(f);
  // The cross product from the face's halfedge tail: corners 2, 0, 1 of its vertex loop.
  std::vector<Eigen::Vector3d> crosses(faces.size());
  parallelBlocks(faces.size(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t f = first; f < last; ++f) {
      const auto& c = faces[f];
      const Eigen::Vector3d p0 = toEigen(surface.point(TriMesh::VertexHandle(c[2])));
      crosses[f] = (toEigen(surface.point(TriMesh::VertexHandle(c[0]))) - p0)
                       .cross(toEigen(surface.point(TriMesh::VertexHandle(c[1]))) - p0);
    }
  });
  std::vector<Eigen::Vector3d> normals(vertices, Eigen::Vector3d::Zero());
  parallelBlocks(vertices, kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t v = first; v < last; ++v)
      for (std::size_t i = start[v]; i < start[v + 1]; ++i)
        normals[v] += crosses[around[i]];
  });
  return normals;
}

std::shared_ptr<const SceneMesh> buildSceneMesh(const RenderItem& item,
                                                const Eigen::Vector3d& centre) {
  auto built = std::make_shared<SceneMesh>();
  SceneMesh& out = *built;
  const TriMesh& surface = item.mesh->surface;
  const auto& colors = item.mesh->vertexColors;
  out.color = item.color;
  out.centre = centre;
  out.faces = faceCorners(surface);
  const std::vector<Eigen::Vector3d> sums = vertexNormals(surface, out.faces);
  const std::size_t vertices = surface.n_vertices();
  out.points.resize(vertices);
  out.positions.resize(vertices);
  out.colors.resize(vertices);
  out.normals.resize(vertices);
  parallelBlocks(vertices, kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t v = first; v < last; ++v) {
      out.points[v] = toEigen(surface.point(TriMesh::VertexHandle(int(v)))) - centre;
      out.positions[v] = toFloats(out.points[v]);
      out.colors[v] = colors.empty() ? item.color : colors[v];
      out.normals[v] = unitOrZero(sums[v]);
    }
  });
  out.faceNormals.resize(out.faces.size());
  out.faceUnits.resize(out.faces.size());
  parallelBlocks(out.faces.size(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t f = first; f < last; ++f) {
      const auto& c = out.faces[f];
      const Eigen::Vector3d& p0 = out.points[std::size_t(c[0])];
      out.faceNormals[f] =
          (out.points[std::size_t(c[1])] - p0).cross(out.points[std::size_t(c[2])] - p0);
      out.faceUnits[f] = unitOrZero(out.faceNormals[f]);
    }
  });
  return built;
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

std::size_t Scene::triangles() const {
  std::size_t count = 0;
  for (const SceneItem& item : items)
    count += item.mesh->faces.size();
  return count;
}

float visibleSide(const Scene& scene, const SceneMesh& mesh, std::size_t face) {
  const Eigen::Vector3d& p0 = mesh.points[std::size_t(mesh.faces[face][0])];
  return mesh.faceNormals[face].dot(scene.eye - p0) < 0 ? -1.0f : 1.0f;
}

std::array<float, 3> cornerNormal(const Scene& scene, const SceneMesh& mesh, std::size_t face,
                                  int k, float side) {
  constexpr std::array<float, 3> kNone{};
  std::array<float, 3> normal = mesh.normals[std::size_t(mesh.faces[face][std::size_t(k)])];
  if (normal == kNone) normal = mesh.faceUnits[face];
  if (normal == kNone) return toFloats(scene.back);
  return {side * normal[0], side * normal[1], side * normal[2]};
}

std::array<std::array<float, 3>, 3> edgeLines(const Scene& scene, const SceneMesh& mesh,
                                              std::size_t face) {
  // Homogeneous window coordinates (pixels, y down) of each corner; the line through two of them
  // is their cross product, even for a corner behind the eye.
  std::array<Eigen::Vector3d, 3> window;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& point = mesh.points[std::size_t(mesh.faces[face][std::size_t(k)])];
    const Eigen::Vector4d clip = scene.viewProjection * point.homogeneous();
    window[k] = {0.5 * (clip.x() + clip.w()) * scene.width,
                 0.5 * (clip.y() + clip.w()) * scene.height, clip.w()};
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

void writeCorners(const Scene& scene, SceneVertex* out) {
  for (const SceneItem& item : scene.items) {
    const SceneMesh& mesh = *item.mesh;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const float side = visibleSide(scene, mesh, f);
      // Only a wireframe reads the edge lines (weighted by 0 elsewhere).
      const auto lines =
          item.wireframe ? edgeLines(scene, mesh, f) : std::array<std::array<float, 3>, 3>{};
      for (int k = 0; k < 3; ++k) {
        const std::size_t v = std::size_t(mesh.faces[f][std::size_t(k)]);
        SceneVertex& vertex = *out++;
        vertex.position = mesh.positions[v];
        vertex.normal = cornerNormal(scene, mesh, f, k, side);
        vertex.color = mesh.colors[v];
        vertex.edgeLines = lines;
        vertex.wireframe = item.wireframe ? 1.0f : 0.0f;
      }
    }
  }
}

namespace {

// The scene of one render: the kept geometry where it was drawn in the same colour around the same
// centre, else built anew (and kept).
Scene prepareScene(const std::vector<RenderItem>& items, const RenderOptions& options,
                   std::vector<Renderer::KeptMesh>& kept, std::size_t& builds) {
  const auto [framing, camera] = prepareCamera(items, options, kept);
  Scene scene;
  scene.width = options.width;
  scene.height = options.height;
  for (std::size_t i = 0; i < items.size(); ++i) {
    std::shared_ptr<const SceneMesh>& geometry = kept[i].geometry;
    if (!geometry || geometry->centre != framing.center || geometry->color != items[i].color) {
      geometry = buildSceneMesh(items[i], framing.center);
      ++builds;
    }
    scene.items.push_back({geometry, items[i].wireframe});
  }
  scene.eye = camera.eye;
  scene.back = camera.back;
  scene.viewProjection = camera.viewProjection;
  scene.constants = shadingConstants(camera);
  for (int c = 0; c < 3; ++c)
    scene.background[c] = toUnorm8(options.background[c]);
  scene.background[3] = 255;
  return scene;
}

// Auto draws on the CPU rasterizer: the Vulkan path's per-frame upload and read-back cost more
// than the rasterizer's drawing on lavapipe and on a GPU alike (BENCHMARKS.md, "Vulkan on a GPU"),
// and the CPU's images are the same on every machine.
RenderResult draw(const Scene& scene, RenderBackend backend) {
  if (backend != RenderBackend::Vulkan) return {renderCpu(scene), "cpu", "cpu rasterizer"};
  gpu::VulkanContext* context = gpu::VulkanContext::shared();
  if (!context)
    throw std::runtime_error("renderMeshes: the Vulkan backend is unavailable: " +
                             gpu::VulkanContext::unavailableReason());
  return {renderVulkan(scene, *context), "vulkan", context->deviceName()};
}

RenderCamera publicCamera(const Framing& framing, const Camera& camera,
                          const RenderOptions& options) {
  // The scene is drawn relative to the framed centre (float precision); the public camera
  // takes world points.
  Eigen::Matrix4d toCentre = Eigen::Matrix4d::Identity();
  toCentre.block<3, 1>(0, 3) = -framing.center;
  return {camera.viewProjection * toCentre, camera.eye + framing.center, options.width,
          options.height};
}

}  // namespace
}  // namespace detail

double framedRadiiPerPixel(const RenderView& view, int width, int height) {
  // The view's height at the fitted distance of a unit sphere, over its pixels.
  const double distance = detail::fittedDistance(1, view, width, height);
  return 2 * distance * std::tan(view.fovDeg * M_PI / 360) / height;
}

RenderCamera renderCamera(const std::vector<RenderItem>& items, const RenderOptions& options) {
  std::vector<Renderer::KeptMesh> none;
  const auto [framing, camera] = detail::prepareCamera(items, options, none);
  return detail::publicCamera(framing, camera, options);
}

Renderer::Renderer() = default;
Renderer::~Renderer() = default;

RenderResult Renderer::render(const std::vector<RenderItem>& items, const RenderOptions& options) {
  const detail::Scene scene = detail::prepareScene(items, options, kept_, geometryBuilds_);
  return detail::draw(scene, options.backend);
}

Renderer::Prepared Renderer::prepare(const RenderItem& item,
                                     const std::optional<RenderFrame>& frame) {
  std::shared_ptr<KeptMesh> prepared;
  try {
    prepared = std::make_shared<KeptMesh>(detail::checkedEntry(item, 0));
  } catch (const std::runtime_error&) {
    return nullptr;
  }
  const Eigen::Vector3d centre =
      frame ? Eigen::Vector3d(frame->center.data()) : prepared->box.center();
  prepared->geometry = detail::buildSceneMesh(item, centre);
  return prepared;
}

void Renderer::keep(const Prepared& prepared) {
  if (!prepared) return;
  auto same = std::find_if(kept_.begin(), kept_.end(),
                           [&](const KeptMesh& k) { return k.mesh == prepared->mesh; });
  if (same != kept_.end())
    *same = *prepared;
  else
    kept_.push_back(*prepared);
}

RenderCamera Renderer::camera(const std::vector<RenderItem>& items, const RenderOptions& options) {
  const auto [framing, camera] = detail::prepareCamera(items, options, kept_);
  return detail::publicCamera(framing, camera, options);
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
  return Renderer().render(items, options);
}

}  // namespace geobrush
