// The CPU backend of renderMeshes(): a z-buffered rasterizer that follows the
// Vulkan rules (pixel centres at +0.5, vertices snapped to 1/256 pixel as
// llvmpipe does, top-left fill rule, depth 0..1 with LESS, perspective-correct
// attributes) and shades like shaders/mesh.frag.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>

#include "geobrush/parallel.hpp"
#include "render_scene.hpp"

namespace geobrush::detail {
namespace {

constexpr int kSubpixelBits = 8;
constexpr std::int64_t kSubpixels = 1 << kSubpixelBits;
// Clipping against planes this far outside the view keeps the fixed-point
// coordinates small without moving any edge that is on screen.
constexpr float kGuardBand = 4;

// A triangle corner in clip space with the attributes to interpolate.
struct ClipVertex {
  Eigen::Vector4f clip;
  Eigen::Vector3f normal, color;
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& b, float t) {
  return {a.clip + t * (b.clip - a.clip), a.normal + t * (b.normal - a.normal),
          a.color + t * (b.color - a.color)};
}

// What the fragment stage reads per triangle rather than per corner.
struct Wireframe {
  std::array<Eigen::Vector3f, 3> edgeLines;
  float weight = 0;
};

// Planes p with p·clip ≥ 0 inside: Vulkan's depth range 0 ≤ z ≤ w, and the guard band in x, y.
const std::array<Eigen::Vector4f, 6> kClipPlanes = {
    Eigen::Vector4f(0, 0, 1, 0),          Eigen::Vector4f(0, 0, -1, 1),
    Eigen::Vector4f(1, 0, 0, kGuardBand), Eigen::Vector4f(-1, 0, 0, kGuardBand),
    Eigen::Vector4f(0, 1, 0, kGuardBand), Eigen::Vector4f(0, -1, 0, kGuardBand)};

// Sutherland–Hodgman against every plane; the result is a convex polygon.
std::vector<ClipVertex> clipPolygon(std::vector<ClipVertex> polygon) {
  for (const Eigen::Vector4f& plane : kClipPlanes) {
    std::vector<ClipVertex> kept;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const ClipVertex& a = polygon[i];
      const ClipVertex& b = polygon[(i + 1) % polygon.size()];
      const float da = plane.dot(a.clip);
      const float db = plane.dot(b.clip);
      if (da >= 0) kept.push_back(a);
      if ((da >= 0) != (db >= 0)) kept.push_back(lerp(a, b, da / (da - db)));
    }
    polygon = std::move(kept);
    if (polygon.empty()) break;
  }
  return polygon;
}

bool insideAllPlanes(const std::array<ClipVertex, 3>& triangle) {
  for (const ClipVertex& v : triangle)
    for (const Eigen::Vector4f& plane : kClipPlanes)
      if (plane.dot(v.clip) < 0) return false;
  return true;
}

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

std::int64_t ceilDiv(std::int64_t a, std::int64_t b) {
  return -floorDiv(-a, b);
}

// The rows [rowBegin, rowEnd) of a render: every triangle in draw order, each pixel shaded by
// the nearest so far. Bands of rows are independent, so that they can be drawn at once.
class Rasterizer {
 public:
  // clips[i][v]: vertex v of item i in clip space; windowY the same vertex's window row (NaN
  // behind the eye).
  struct Vertices {
    std::vector<std::vector<Eigen::Vector4f>> clips;
    std::vector<std::vector<float>> windowY;
  };

  Rasterizer(const Scene& scene, const Vertices& vertices, Image& image, std::vector<float>& depth,
             int rowBegin, int rowEnd)
      : scene_(scene),
        vertices_(vertices),
        image_(image),
        depth_(depth),
        rowBegin_(rowBegin),
        rowEnd_(rowEnd) {
    const auto& k = scene.constants;
    headlight_ = Eigen::Vector4f(k.headlight.data());
    fillLight_ = Eigen::Vector4f(k.fillLight.data());
    ambient_ = k.material[0];
    edgeGrey_ = k.material[1];
  }

  void run() {
    for (std::size_t i = 0; i < scene_.items.size(); ++i) {
      const SceneMesh& mesh = *scene_.items[i].mesh;
      const bool wire = scene_.items[i].wireframe;
      for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        if (mayCoverBand(mesh.faces[f], vertices_.windowY[i])) drawFace(mesh, f, i, wire);
    }
  }

 private:
  // False only where the face lies wholly above or below the band (a row of margin either way);
  // a face with a corner behind the eye is clipped first, so it may cover any row.
  bool mayCoverBand(const std::array<int, 3>& face, const std::vector<float>& windowY) const {
    const float a = windowY[std::size_t(face[0])], b = windowY[std::size_t(face[1])],
                c = windowY[std::size_t(face[2])];
    if (std::isnan(a) || std::isnan(b) || std::isnan(c)) return true;
    return std::max({a, b, c}) >= float(rowBegin_ - 1) && std::min({a, b, c}) <= float(rowEnd_ + 1);
  }

  void drawFace(const SceneMesh& mesh, std::size_t f, std::size_t item, bool wire) {
    const float side = visibleSide(scene_, mesh, f);
    std::array<ClipVertex, 3> triangle;
    for (int k = 0; k < 3; ++k) {
      const std::size_t v = std::size_t(mesh.faces[f][std::size_t(k)]);
      triangle[k] = {vertices_.clips[item][v],
                     Eigen::Vector3f(cornerNormal(scene_, mesh, f, k, side).data()),
                     Eigen::Vector3f(mesh.colors[v].data())};
    }
    Wireframe wireframe;
    if (wire) {
      const auto lines = edgeLines(scene_, mesh, f);
      for (int k = 0; k < 3; ++k)
        wireframe.edgeLines[k] = Eigen::Vector3f(lines[k].data());
      wireframe.weight = 1;
    } else {
      wireframe.edgeLines.fill(Eigen::Vector3f::Zero());
    }
    drawClipped(triangle, wireframe);
  }

  void drawClipped(const std::array<ClipVertex, 3>& triangle, const Wireframe& wireframe) {
    if (insideAllPlanes(triangle)) return drawTriangle(triangle, wireframe);
    const std::vector<ClipVertex> polygon =
        clipPolygon(std::vector<ClipVertex>(triangle.begin(), triangle.end()));
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
      drawTriangle({polygon[0], polygon[i], polygon[i + 1]}, wireframe);
  }

  // Fixed-point window coordinates; y grows downwards.
  struct Corner {
    std::int64_t x, y;
    float z, invW;
  };

  Corner toWindow(const ClipVertex& v) const {
    const float invW = 1.0f / v.clip.w();
    const float x = (v.clip.x() * invW * 0.5f + 0.5f) * float(scene_.width);
    const float y = (v.clip.y() * invW * 0.5f + 0.5f) * float(scene_.height);
    return {std::lrint(x * kSubpixels), std::lrint(y * kSubpixels), v.clip.z() * invW, invW};
  }

  // Edge a→b is positive on its inner side once the triangle is ordered so
  // that its area is positive.
  static std::int64_t edge(const Corner& a, const Corner& b, std::int64_t x, std::int64_t y) {
    return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
  }

  // With y down, a top edge is horizontal with the inside below it and a
  // left edge has the inside to its right; samples on those edges are in.
  static std::int64_t fillBias(const Corner& a, const Corner& b) {
    const bool top = a.y == b.y && b.x > a.x;
    const bool left = b.y < a.y;
    return top || left ? 0 : -1;
  }

  void drawTriangle(std::array<ClipVertex, 3> v, const Wireframe& wireframe) {
    std::array<Corner, 3> c = {toWindow(v[0]), toWindow(v[1]), toWindow(v[2])};
    std::int64_t area = edge(c[0], c[1], c[2].x, c[2].y);
    if (area == 0) return;
    if (area < 0) {
      std::swap(v[1], v[2]);
      std::swap(c[1], c[2]);
      area = -area;
    }
    // Edge i is opposite corner i.
    const std::array<std::pair<int, int>, 3> edges = {{{1, 2}, {2, 0}, {0, 1}}};
    std::array<std::int64_t, 3> bias, stepX, stepY;
    for (int i = 0; i < 3; ++i) {
      const Corner& a = c[edges[i].first];
      const Corner& b = c[edges[i].second];
      bias[i] = fillBias(a, b);
      stepX[i] = -(b.y - a.y) * kSubpixels;
      stepY[i] = (b.x - a.x) * kSubpixels;
    }

    const std::int64_t half = kSubpixels / 2;
    const auto [minX, maxX] = std::minmax({c[0].x, c[1].x, c[2].x});
    const auto [minY, maxY] = std::minmax({c[0].y, c[1].y, c[2].y});
    const int x0 = int(std::max<std::int64_t>(ceilDiv(minX - half, kSubpixels), 0));
    const int x1 = int(std::min<std::int64_t>(floorDiv(maxX - half, kSubpixels), scene_.width - 1));
    const int y0 = int(std::max<std::int64_t>(ceilDiv(minY - half, kSubpixels), rowBegin_));
    const int y1 = int(std::min<std::int64_t>(floorDiv(maxY - half, kSubpixels), rowEnd_ - 1));
    if (x0 > x1 || y0 > y1) return;

    const float invArea = 1.0f / float(area);
    for (int y = y0; y <= y1; ++y) {
      std::array<std::int64_t, 3> e;
      for (int i = 0; i < 3; ++i)
        e[i] = edge(c[edges[i].first], c[edges[i].second], x0 * kSubpixels + half,
                    y * kSubpixels + half);
      for (int x = x0; x <= x1; ++x) {
        if (e[0] + bias[0] >= 0 && e[1] + bias[1] >= 0 && e[2] + bias[2] >= 0) {
          const Eigen::Vector3f lambda(e[0] * invArea, e[1] * invArea, e[2] * invArea);
          shadeSample(x, y, lambda, v, c, wireframe);
        }
        for (int i = 0; i < 3; ++i)
          e[i] += stepX[i];
      }
    }
  }

  void shadeSample(int x, int y, const Eigen::Vector3f& lambda, const std::array<ClipVertex, 3>& v,
                   const std::array<Corner, 3>& c, const Wireframe& wireframe) {
    const float z = lambda[0] * c[0].z + lambda[1] * c[1].z + lambda[2] * c[2].z;
    float& stored = depth_[std::size_t(y) * scene_.width + x];
    if (!(z < stored)) return;
    stored = z;

    Eigen::Vector3f weights(lambda[0] * c[0].invW, lambda[1] * c[1].invW, lambda[2] * c[2].invW);
    weights /= weights.sum();
    const Eigen::Vector3f normal =
        weights[0] * v[0].normal + weights[1] * v[1].normal + weights[2] * v[2].normal;
    const Eigen::Vector3f color =
        weights[0] * v[0].color + weights[1] * v[1].color + weights[2] * v[2].color;
    float edgeAmount = 0;
    if (wireframe.weight > 0) {
      const Eigen::Vector3f pixel(float(x) + 0.5f, float(y) + 0.5f, 1.0f);
      float nearestEdge = std::numeric_limits<float>::infinity();
      for (const Eigen::Vector3f& line : wireframe.edgeLines)
        nearestEdge = std::min(nearestEdge, std::abs(line.dot(pixel)));
      edgeAmount = wireframe.weight * (1 - std::clamp(nearestEdge - 0.5f, 0.0f, 1.0f));
    }
    std::uint8_t* pixel = image_.pixel(x, y);
    const Eigen::Vector3f shaded = shade(normal, color, edgeAmount);
    for (int k = 0; k < 3; ++k)
      pixel[k] = toUnorm8(shaded[k]);
    pixel[3] = 255;
  }

  // shaders/mesh.frag, term by term; returns a colour clamped to [0, 1].
  Eigen::Vector3f shade(const Eigen::Vector3f& interpolatedNormal, const Eigen::Vector3f& color,
                        float edgeAmount) const {
    const float length = interpolatedNormal.norm();
    const Eigen::Vector3f normal =
        length > 1e-20f ? Eigen::Vector3f(interpolatedNormal / length) : headlight_.head<3>();
    const float light = ambient_ +
                        headlight_.w() * std::max(normal.dot(headlight_.head<3>()), 0.0f) +
                        fillLight_.w() * std::max(normal.dot(fillLight_.head<3>()), 0.0f);
    const Eigen::Vector3f lit =
        (1 - edgeAmount) * (color * light) + edgeAmount * Eigen::Vector3f::Constant(edgeGrey_);
    return lit.cwiseMax(0.0f).cwiseMin(1.0f);
  }

  const Scene& scene_;
  const Vertices& vertices_;
  Image& image_;
  std::vector<float>& depth_;
  int rowBegin_, rowEnd_;
  Eigen::Vector4f headlight_, fillLight_;
  float ambient_ = 0, edgeGrey_ = 0;
};

}  // namespace

Image renderCpu(const Scene& scene) {
  Image image(scene.width, scene.height);
  std::vector<float> depth(std::size_t(scene.width) * scene.height, 1.0f);
  for (std::size_t i = 0; i < depth.size(); ++i)
    std::copy(scene.background.begin(), scene.background.end(), &image.rgba[4 * i]);
  // Each vertex once into clip space, as the vertex stage does for every corner.
  const Eigen::Matrix4f viewProjection(scene.constants.viewProjection.data());
  Rasterizer::Vertices vertices;
  for (const SceneItem& item : scene.items) {
    const auto& positions = item.mesh->positions;
    auto& clips = vertices.clips.emplace_back(positions.size());
    auto& windowY = vertices.windowY.emplace_back(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
      const auto& p = positions[v];
      clips[v] = viewProjection * Eigen::Vector4f(p[0], p[1], p[2], 1);
      windowY[v] = clips[v].w() > 0
                       ? (clips[v].y() / clips[v].w() * 0.5f + 0.5f) * float(scene.height)
                       : std::numeric_limits<float>::quiet_NaN();
    }
  }
  // A band of rows per thread: a pixel sees the same triangles in the same order in any band.
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t rows = std::size_t(scene.height);
  parallelBlocks(rows, (rows + std::size_t(threads) - 1) / std::size_t(threads), threads,
                 [&](std::size_t first, std::size_t last) {
                   Rasterizer(scene, vertices, image, depth, int(first), int(last)).run();
                 });
  return image;
}

}  // namespace geobrush::detail
