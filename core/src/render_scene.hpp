// What both renderers draw: each mesh's geometry, prepared once whatever the camera (positions
// relative to the framed centre, unit smooth normals, colours, faces), and the camera and lights of
// one render. The CPU rasterizer reads the meshes as they are; the Vulkan backend expands them to
// independent triangles whose normals are already turned towards the camera. Both take every
// decision from the same prepared numbers, so they differ in rasterization and float rounding
// alone.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "geobrush/render.hpp"

namespace geobrush::gpu {
class VulkanContext;
}

namespace geobrush::detail {

// One mesh drawn in one colour around one centre, independent of the camera: what a Renderer
// keeps from frame to frame while it draws the same mesh.
struct SceneMesh {
  Rgb color{};
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> points;          // per vertex, relative to the centre
  std::vector<std::array<float, 3>> positions;  // the same in float, as drawn
  std::vector<std::array<float, 3>> normals;    // per vertex: unit, area-weighted; zero where none
  std::vector<std::array<float, 3>> colors;     // per vertex
  std::vector<std::array<int, 3>> faces;        // vertex indices, in the mesh's face order
  std::vector<Eigen::Vector3d> faceNormals;     // cross products of two edges (twice the area)
  std::vector<std::array<float, 3>> faceUnits;  // the same, unit; zero where degenerate
};

// One triangle corner, laid out as shaders/mesh.vert reads it.
struct SceneVertex {
  std::array<float, 3> position;  // relative to the centre of the bounding box
  std::array<float, 3> normal;    // unit; flipped where the triangle faces away
  std::array<float, 3> color;     // linear RGB
  // The triangle's edges (opposite corners 0, 1, 2) as lines a x + b y + c = 0
  // in window pixels with a² + b² = 1, so |a x + b y + c| is the distance in
  // pixels; the same in all three corners.
  std::array<std::array<float, 3>, 3> edgeLines;
  float wireframe;  // 1 where the edges are drawn, else 0
};

// The push-constant block of shaders/mesh.vert and shaders/mesh.frag.
struct ShadingConstants {
  // Column-major, to Vulkan clip space: y down, depth 0 (near) to 1 (far).
  std::array<float, 16> viewProjection;
  std::array<float, 4> headlight;  // xyz: unit direction towards the light; w: weight
  std::array<float, 4> fillLight;  // as headlight
  std::array<float, 4> material;   // x: ambient weight; y: grey level of wireframe edges
};
static_assert(sizeof(ShadingConstants) == 112, "must match the GLSL push-constant block");

struct SceneItem {
  std::shared_ptr<const SceneMesh> mesh;
  bool wireframe = false;
};

struct Scene {
  int width = 0;
  int height = 0;
  std::vector<SceneItem> items;
  // The camera, relative to the framed centre.
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  Eigen::Vector3d back = Eigen::Vector3d::UnitZ();  // the unit direction towards the eye
  Eigen::Matrix4d viewProjection = Eigen::Matrix4d::Identity();
  ShadingConstants constants{};
  std::array<std::uint8_t, 4> background{};  // RGBA8

  std::size_t triangles() const;
};

// Which side of face f of `mesh` the camera sees: 1 its front, -1 its back (two-sided lighting).
float visibleSide(const Scene& scene, const SceneMesh& mesh, std::size_t face);
// The normal of corner k of face f as drawn: the vertex's smooth normal turned to the visible
// side; the face's own where the vertex has none; the view direction where neither has one.
std::array<float, 3> cornerNormal(const Scene& scene, const SceneMesh& mesh, std::size_t face,
                                  int k, float side);
// The window-pixel lines through face f's edges (SceneVertex::edgeLines), for wireframes.
std::array<std::array<float, 3>, 3> edgeLines(const Scene& scene, const SceneMesh& mesh,
                                              std::size_t face);
// Every triangle's three corners, in draw order, into out[0 .. 3 * triangles()).
void writeCorners(const Scene& scene, SceneVertex* out);

// The rounding to 8 bits that the Vulkan colour attachment applies too: round(255 v), halves away
// from zero, as std::lround (exact in double, where v + 0.5 loses nothing), inlined for the
// rasterizer's every pixel.
inline std::uint8_t toUnorm8(float value) {
  const float scaled = std::clamp(value, 0.0f, 1.0f) * 255.0f;
  return static_cast<std::uint8_t>(double(scaled) + 0.5);
}

Image renderCpu(const Scene& scene);
Image renderVulkan(const Scene& scene, gpu::VulkanContext& context);

}  // namespace geobrush::detail
