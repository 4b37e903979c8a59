// Offscreen rendering of shaded meshes into an Image: Vulkan when a device
// is found (a GPU, else lavapipe), with a CPU rasterizer twin.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/image.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/param.hpp"

namespace geobrush {

struct RenderItem {
  MeshPtr mesh;
  Rgb color{0.78f, 0.78f, 0.80f};  // used where the mesh has no vertex colours
  bool wireframe = false;          // draw triangle edges over the shading
};

// An orbit camera around the bounding box of everything drawn.
struct RenderView {
  double azimuthDeg = 30;    // around +y, from +z towards +x
  double elevationDeg = 20;  // above the xz plane
  double fovDeg = 35;        // vertical field of view
  double zoom = 1;           // > 1 moves closer than the fitted distance
  // Moves the point looked at along the camera's right and up axes, in radii of the framed
  // sphere (what dragging a viewport pans).
  double panRight = 0;
  double panUp = 0;
};

// A sphere to frame instead of the items' bounding box: a viewport keeps its camera while the
// meshes it shows change.
struct RenderFrame {
  std::array<double, 3> center{0, 0, 0};
  double radius = 1;
};

// The inclusive ranges of a render's size and camera, shared by the geobrush.render node's params
// and the options of `geobrush render`: one source, so that both accept the same values.
struct RenderRange {
  double min;
  double max;
};
inline constexpr RenderRange kRenderSizeRange{16, 8192};      // width and height, in pixels
inline constexpr RenderRange kRenderAzimuthRange{-360, 360};  // degrees
inline constexpr RenderRange kRenderElevationRange{-89, 89};  // degrees; the poles have no "up"
inline constexpr RenderRange kRenderFovRange{5, 120};         // degrees
inline constexpr RenderRange kRenderZoomRange{0.05, 50};
// The largest radius a render may frame (geobrush.render's focus_radius, --focus-radius).
inline constexpr double kRenderFocusRadiusMax = 1e30;

enum class RenderBackend { Auto, Vulkan, Cpu };

struct RenderOptions {
  int width = 800;
  int height = 600;
  RenderView view;
  Rgb background{1.0f, 1.0f, 1.0f};
  RenderBackend backend = RenderBackend::Auto;
  std::optional<RenderFrame> frame;  // none: the bounding box of the items
};

struct RenderResult {
  Image image;
  std::string backend;  // "vulkan" or "cpu"
  std::string device;   // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or "cpu rasterizer"
};

// The camera of a render, in world coordinates: what overlays are projected with and what
// picking casts rays from, so both line up with the image pixel for pixel.
struct RenderCamera {
  Eigen::Matrix4d viewProjection;  // world -> clip space (Vulkan: y down, depth 0 near .. 1 far)
  Eigen::Vector3d eye;
  int width = 0;
  int height = 0;

  // Window position (pixels, y down) and depth (0 near .. 1 far) of a point; none behind the eye.
  std::optional<Eigen::Vector3d> project(const Eigen::Vector3d& point) const;
  // The ray through window position (x, y): the eye and a unit direction.
  std::pair<Eigen::Vector3d, Eigen::Vector3d> ray(double x, double y) const;
};

// Radii of the framed sphere per pixel, in the plane through the point looked at, across the
// view: how far RenderView's pan moves for one pixel (an interactive view's pan and zoom).
double framedRadiiPerPixel(const RenderView& view, int width, int height);

// Throws std::runtime_error for the same options renderMeshes refuses.
RenderCamera renderCamera(const std::vector<RenderItem>& items, const RenderOptions& options);

// Throws std::runtime_error if nothing can be drawn (no faces, bad size) or
// the Vulkan backend was asked for and is unavailable. Auto draws on the CPU
// rasterizer, Vulkan on the shared device.
RenderResult renderMeshes(const std::vector<RenderItem>& items, const RenderOptions& options = {});

namespace detail {
struct SceneMesh;
}

// Draws frame after frame, as an interactive view does: keeps each mesh's geometry that no camera
// changes (its checks, bounding box, normals, positions around the framed centre, colours) while
// the same mesh value is drawn in the same colour around the same centre, so that a new view of
// it costs the camera's work alone. It holds the meshes of its last render (a shared value is
// never changed). Its images and cameras are renderMeshes' and renderCamera's, bit for bit.
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  RenderResult render(const std::vector<RenderItem>& items, const RenderOptions& options);
  RenderCamera camera(const std::vector<RenderItem>& items, const RenderOptions& options);

  struct KeptMesh;
  // An item's checks, box and geometry made ahead of the frame that draws it, on any thread (a
  // view prepares its next mesh while it still shows the current one): built around `frame`'s
  // centre, else the mesh's box centre (where a render of the item alone frames it). Null where
  // a render would refuse the item. keep() hands it to a renderer; a render of that item around
  // that centre then skips the work, and any other render ignores it: images stay the same.
  using Prepared = std::shared_ptr<const KeptMesh>;
  static Prepared prepare(const RenderItem& item, const std::optional<RenderFrame>& frame);
  void keep(const Prepared& prepared);
  // How many times a render built a mesh's geometry itself (for tests).
  std::size_t geometryBuilds() const { return geometryBuilds_; }

 private:
  std::vector<KeptMesh> kept_;
  std::size_t geometryBuilds_ = 0;
};

}  // namespace geobrush
