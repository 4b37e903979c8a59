// The texture copy of "Mesh Geometric Editing Approach Based on GPU Texture" (alternatives spec
// 1.2, "Texture copy", E2/E3), with its CPU twin of shaders/texture_raster.comp.
#include "texture_roi.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "geobrush/region_support.hpp"
#include "texture_raster_vulkan.hpp"

namespace geobrush {
namespace {

constexpr std::int64_t kTexelFixed = std::int64_t(1) << kSubtexelBits;
// Corners beyond this (in fixed point) could overflow the kernel's 32-bit differences.
constexpr std::int64_t kMaxFixed = std::int64_t(1) << 29;

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// The texels whose centres, 256 i + 128 in fixed point, lie in [lo, hi], clamped to [0, N - 1].
void texelRange(std::int64_t lo, std::int64_t hi, int size, int& first, int& last) {
  first = int(std::max<std::int64_t>(0, -floorDiv(-(lo - kTexelFixed / 2), kTexelFixed)));
  last = int(std::min<std::int64_t>(size - 1, floorDiv(hi - kTexelFixed / 2, kTexelFixed)));
}

struct TexelBox {
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  bool empty() const { return i0 > i1 || j0 > j1; }
};

TexelBox texelBox(const std::int32_t* corners, int size) {
  const std::int64_t xLo = std::min({corners[0], corners[2], corners[4]});
  const std::int64_t xHi = std::max({corners[0], corners[2], corners[4]});
  const std::int64_t yLo = std::min({corners[1], corners[3], corners[5]});
  const std::int64_t yHi = std::max({corners[1], corners[3], corners[5]});
  TexelBox box;
  texelRange(xLo, xHi, size, box.i0, box.i1);
  texelRange(yLo, yHi, size, box.j0, box.j1);
  return box;
}

std::int64_t cross(std::int64_t dx, std::int64_t dy, std::int64_t rx, std::int64_t ry) {
  return dx * ry - dy * rx;
}

// The kernel's fill rule (see owns() in shaders/texture_raster.comp).
bool owns(std::int64_t dx, std::int64_t dy) {
  return dy < 0 || (dy == 0 && dx > 0);
}

bool holds(std::int64_t e, std::int64_t dx, std::int64_t dy) {
  return e > 0 || (e == 0 && owns(dx, dy));
}

// Whether the counter-clockwise fixed-point triangle holds the texel centre (px, py), with the
// edge weights of its corners 1 and 2 there: the kernel's test, in int64 instead of word pairs.
bool holdsCentre(const std::int32_t* c, std::int64_t px, std::int64_t py, std::int64_t& w1,
                 std::int64_t& w2) {
  const std::int64_t x0 = c[0], y0 = c[1], x1 = c[2], y1 = c[3], x2 = c[4], y2 = c[5];
  const std::int64_t e0 = cross(x2 - x1, y2 - y1, px - x1, py - y1);
  w1 = cross(x0 - x2, y0 - y2, px - x2, py - y2);
  w2 = cross(x1 - x0, y1 - y0, px - x0, py - y0);
  return holds(e0, x2 - x1, y2 - y1) && holds(w1, x0 - x2, y0 - y2) && holds(w2, x1 - x0, y1 - y0);
}

// A face's corners in fixed point, in the order of the canvas mesh. False where a uv is not
// finite.
bool snapFace(const Parameterization& param, const DomainGrid& grid, TriMesh::FaceHandle f,
              std::array<std::int64_t, 6>& xy, std::array<int, 3>& corners) {
  int k = 0;
  for (auto v : param.canvas->surface.fv_range(f)) {
    corners[std::size_t(k)] = v.idx();
    const Eigen::Vector2d t = (param.uv[std::size_t(v.idx())] - grid.origin) / grid.spacing;
    const Eigen::Vector2d fixed = (t.array() + 0.5) * double(kTexelFixed);
    if (!fixed.allFinite()) return false;
    // Clamped before rounding: a corner this far out is refused later anyway.
    xy[std::size_t(2 * k)] = std::llround(std::clamp(fixed.x(), -4.0 * kMaxFixed, 4.0 * kMaxFixed));
    xy[std::size_t(2 * k + 1)] =
        std::llround(std::clamp(fixed.y(), -4.0 * kMaxFixed, 4.0 * kMaxFixed));
    ++k;
  }
  return k == 3;
}

// The height h the face keeps along the canvas' normal: the mean of its corners'.
double faceHeight(const Parameterization& param, const std::array<int, 3>& corners) {
  const TriMesh& mesh = param.canvas->surface;
  double h = 0;
  for (int v : corners) {
    const Eigen::Vector3d x = toEigen(mesh.point(TriMesh::VertexHandle(v)));
    h += (x - param.origin.point).dot(param.origin.normal);
  }
  return h / 3;
}

struct KeptFace {
  int id;
  double height;
  std::array<std::int32_t, 6> xy;
};

// Snaps and orients every face that reaches the texture, and fills the per-face arrays.
std::vector<KeptFace> keptFaces(const Parameterization& param, const DomainGrid& grid,
                                RasterFaces& raster) {
  const TriMesh& mesh = param.canvas->surface;
  raster.doubleArea.assign(mesh.n_faces(), 0);
  raster.flipped.assign(mesh.n_faces(), 0);
  std::vector<KeptFace> kept;
  for (auto f : mesh.faces()) {
    std::array<std::int64_t, 6> xy;
    std::array<int, 3> corners;
    if (!snapFace(param, grid, f, xy, corners))
      throw TextureRoiError("a canvas vertex has no finite uv");
    std::array<std::int32_t, 6> clamped;
    for (std::size_t k = 0; k < 6; ++k)
      clamped[k] = std::int32_t(std::clamp(xy[k], -kMaxFixed, kMaxFixed));
    if (texelBox(clamped.data(), raster.size).empty()) continue;
    for (std::size_t k = 0; k < 6; ++k)
      if (clamped[k] != xy[k])
        throw TextureRoiError(
            "a canvas face reaches the texture with a corner more than 2^21 texels away");
    std::int64_t area = cross(xy[2] - xy[0], xy[3] - xy[1], xy[4] - xy[0], xy[5] - xy[1]);
    if (area == 0) continue;
    const std::size_t id = std::size_t(f.idx());
    if (area < 0) {
      std::swap(clamped[2], clamped[4]);
      std::swap(clamped[3], clamped[5]);
      area = -area;
      raster.flipped[id] = 1;
    }
    raster.doubleArea[id] = area;
    kept.push_back({f.idx(), faceHeight(param, corners), clamped});
  }
  // The depth test along -n_P [ours]: highest first, ties to the lowest face id.
  std::sort(kept.begin(), kept.end(), [](const KeptFace& a, const KeptFace& b) {
    return a.height != b.height ? a.height > b.height : a.id < b.id;
  });
  return kept;
}

// Lists the ordered faces per tile they reach: counts, then the entries in order.
void binFaces(RasterFaces& raster) {
  const int tiles = raster.tilesPerSide;
  raster.tileStart.assign(std::size_t(tiles) * std::size_t(tiles) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::int32_t> filled(raster.tileStart.begin(), raster.tileStart.end() - 1);
    for (std::size_t k = 0; k < raster.faceCount(); ++k) {
      const TexelBox box = texelBox(&raster.faces[k * RasterFaces::kFaceInts], raster.size);
      for (int ty = box.j0 / kTextureTile; ty <= box.j1 / kTextureTile; ++ty)
        for (int tx = box.i0 / kTextureTile; tx <= box.i1 / kTextureTile; ++tx) {
          const std::size_t tile = std::size_t(ty) * std::size_t(tiles) + std::size_t(tx);
          if (pass == 0)
            ++raster.tileStart[tile + 1];
          else
            raster.tileFaces[std::size_t(filled[tile]++)] = std::int32_t(k);
        }
    }
    if (pass == 0) {
      std::partial_sum(raster.tileStart.begin(), raster.tileStart.end(), raster.tileStart.begin());
      raster.tileFaces.resize(std::size_t(raster.tileStart.back()));
    }
  }
}

std::vector<int> sortedUnique(const std::vector<char>& marked) {
  std::vector<int> indices;
  for (std::size_t v = 0; v < marked.size(); ++v)
    if (marked[v]) indices.push_back(int(v));
  return indices;
}

// The texel whose square holds u, or -1 outside the texture.
int texelAt(const DomainGrid& grid, const Eigen::Vector2d& u) {
  const Eigen::Vector2d g = (u - grid.origin) / grid.spacing;
  const double i = std::floor(g.x() + 0.5), j = std::floor(g.y() + 0.5);
  if (!(i >= 0 && j >= 0 && i < grid.width && j < grid.height)) return -1;
  return int(grid.index(int(i), int(j)));
}

// The source faces whose texels were all copied; a face that holds no texel follows the texel
// under its uv centroid.
std::vector<char> copiedFaces(const Region2D& region, const NodeWindow& window,
                              const TextureSourceSide& side) {
  const DomainGrid& grid = region.grid;
  const std::vector<std::uint32_t>& face = side.texture.face;
  std::vector<int> copied(side.ownedTexels.size(), 0);
  for (int j = window.j0; j <= window.j1; ++j)
    for (int i = window.i0; i <= window.i1; ++i) {
      const std::size_t t = grid.index(i, j);
      if (region.inside[t]) ++copied[face[t] - 1];
    }
  std::vector<char> selected(copied.size(), 0);
  for (std::size_t f = 0; f < copied.size(); ++f)
    selected[f] = copied[f] > 0 && copied[f] == side.ownedTexels[f];
  for (int f : side.texellessFaces) {
    const int t = side.centroidTexel[std::size_t(f)];
    selected[std::size_t(f)] = t >= 0 && region.inside[std::size_t(t)];
  }
  return selected;
}

std::vector<int> cornersOf(const TriMesh& mesh, const std::vector<char>& faces) {
  std::vector<char> marked(mesh.n_vertices(), 0);
  for (auto f : mesh.faces())
    if (faces[std::size_t(f.idx())])
      for (auto v : mesh.fv_range(f))
        marked[std::size_t(v.idx())] = 1;
  return sortedUnique(marked);
}

// The window grown to hold the texels of the given vertices, as draftSupport needs.
NodeWindow holdingVertices(NodeWindow window, const DomainGrid& grid,
                           const std::vector<Eigen::Vector2d>& uv,
                           const std::vector<int>& vertices) {
  for (int v : vertices) {
    const Eigen::Vector2d g = (uv[std::size_t(v)] - grid.origin) / grid.spacing;
    window.i0 = std::max(0, std::min(window.i0, int(std::floor(g.x()))));
    window.j0 = std::max(0, std::min(window.j0, int(std::floor(g.y()))));
    window.i1 = std::min(grid.width - 1, std::max(window.i1, int(std::ceil(g.x()))));
    window.j1 = std::min(grid.height - 1, std::max(window.j1, int(std::ceil(g.y()))));
  }
  return window;
}

}  // namespace

DomainGrid textureGrid(const Parameterization& source, int size) {
  if (size < kMinTextureSize || size > kMaxTextureSize)
    throw TextureRoiError("the texture size must lie in [16, 4096] texels");
  double radius = 0;
  for (const Eigen::Vector2d& u : source.uv)
    radius = std::max(radius, u.norm());
  if (!(radius > 0) || !std::isfinite(radius))
    throw TextureRoiError("the source domain has no extent");
  const double side = 2 * radius * size / (size - 2 * kTextureBorder);
  DomainGrid grid;
  grid.spacing = side / size;
  grid.origin = Eigen::Vector2d::Constant(-side / 2 + grid.spacing / 2);  // centred on uv 0, as E3
  grid.width = grid.height = size;
  return grid;
}

RasterFaces rasterFaces(const Parameterization& param, const DomainGrid& grid) {
  RasterFaces raster;
  raster.size = grid.width;
  raster.tilesPerSide = (grid.width + kTextureTile - 1) / kTextureTile;
  const std::vector<KeptFace> kept = keptFaces(param, grid, raster);
  raster.faces.assign(kept.size() * RasterFaces::kFaceInts, 0);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    std::int32_t* out = &raster.faces[k * RasterFaces::kFaceInts];
    std::copy(kept[k].xy.begin(), kept[k].xy.end(), out);
    out[6] = kept[k].id;
  }
  binFaces(raster);
  return raster;
}

void rasterizeCpu(const RasterFaces& raster, std::vector<std::uint32_t>& face,
                  std::vector<std::int64_t>& weight) {
  const std::size_t n = std::size_t(raster.size);
  face.assign(n * n, 0);
  weight.assign(2 * n * n, 0);
  // In depth order, the first face that holds a texel keeps it: the kernel's first hit in its
  // tile's list, which holds the same faces in the same order.
  for (std::size_t k = 0; k < raster.faceCount(); ++k) {
    const std::int32_t* c = &raster.faces[k * RasterFaces::kFaceInts];
    const TexelBox box = texelBox(c, raster.size);
    for (int j = box.j0; j <= box.j1; ++j)
      for (int i = box.i0; i <= box.i1; ++i) {
        const std::size_t t = std::size_t(j) * n + std::size_t(i);
        std::int64_t w1, w2;
        if (face[t] != 0 || !holdsCentre(c, i * kTexelFixed + kTexelFixed / 2,
                                         j * kTexelFixed + kTexelFixed / 2, w1, w2))
          continue;
        face[t] = std::uint32_t(c[6] + 1);
        weight[2 * t] = w1;
        weight[2 * t + 1] = w2;
      }
  }
}

CanvasTexture rasterize(const Parameterization& param, const DomainGrid& grid,
                        TextureKernel kernel) {
  const RasterFaces raster = rasterFaces(param, grid);
  CanvasTexture texture;
  texture.grid = grid;
  if (kernel == TextureKernel::Vulkan)
    rasterizeVulkan(raster, texture.face, texture.weight);
  else
    rasterizeCpu(raster, texture.face, texture.weight);
  texture.doubleArea = raster.doubleArea;
  texture.flipped = raster.flipped;
  return texture;
}

Eigen::Vector3d CanvasTexture::barycentric(std::size_t texel) const {
  if (face[texel] == 0) return Eigen::Vector3d::Zero();
  const std::size_t f = face[texel] - 1;
  const std::int64_t w1 = weight[2 * texel], w2 = weight[2 * texel + 1];
  const double area = double(doubleArea[f]);
  const Eigen::Vector3d ordered(double(doubleArea[f] - w1 - w2) / area, double(w1) / area,
                                double(w2) / area);
  return flipped[f] ? Eigen::Vector3d(ordered[0], ordered[2], ordered[1]) : ordered;
}

std::shared_ptr<const TextureSourceSide> textureSourceSide(const Parameterization& source,
                                                           const TextureRoiOptions& options) {
  auto side = std::make_shared<TextureSourceSide>();
  side->texture = rasterize(source, textureGrid(source, options.textureSize), options.kernel);
  const TriMesh& mesh = source.canvas->surface;
  side->ownedTexels.assign(mesh.n_faces(), 0);
  for (std::uint32_t f : side->texture.face)
    if (f != 0) ++side->ownedTexels[f - 1];
  side->centroidTexel.assign(mesh.n_faces(), -1);
  for (auto f : mesh.faces()) {
    if (side->ownedTexels[std::size_t(f.idx())] > 0) continue;
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (auto v : mesh.fv_range(f))
      centroid += source.uv[std::size_t(v.idx())] / 3;
    side->centroidTexel[std::size_t(f.idx())] = texelAt(side->texture.grid, centroid);
    side->texellessFaces.push_back(f.idx());
  }
  return side;
}

std::shared_ptr<const CanvasTexture> textureTargetSide(const Parameterization& target,
                                                       const DomainGrid& grid,
                                                       TextureKernel kernel) {
  return std::make_shared<const CanvasTexture>(rasterize(target, grid, kernel));
}

TextureRoiResult copyTexels(const Strokes& strokes, const Parameterization& source,
                            const Parameterization& target, const TextureSourceSide& sourceSide,
                            const CanvasTexture& targetTexture,
                            const DomainLocator& sourceLocator) {
  const CanvasTexture& sourceTexture = sourceSide.texture;
  if (!(targetTexture.grid == sourceTexture.grid) ||
      sourceSide.ownedTexels.size() != source.canvas->surface.n_faces() ||
      targetTexture.doubleArea.size() != target.canvas->surface.n_faces())
    throw TextureRoiError("the textures were made for other canvases");
  TextureRoiResult result;
  Region2D& region = result.region;
  region.grid = sourceTexture.grid;
  const DomainGrid& grid = region.grid;
  region.inside.assign(grid.nodeCount(), 0);
  const BinnedStrokes painted(strokes, grid);
  const NodeWindow window = paintedWindow(strokes, grid);
  for (int j = window.j0; j <= window.j1; ++j)
    for (int i = window.i0; i <= window.i1; ++i) {
      const std::size_t t = grid.index(i, j);
      region.inside[t] =
          sourceTexture.face[t] && targetTexture.face[t] && painted.contains(grid.position(i, j));
    }
  region.sourceVertices =
      cornersOf(source.canvas->surface, copiedFaces(region, window, sourceSide));
  for (std::size_t v = 0; v < target.uv.size(); ++v) {
    const int t = texelAt(grid, target.uv[v]);
    if (t >= 0 && region.inside[std::size_t(t)]) region.targetVertices.push_back(int(v));
  }
  const NodeWindow support = holdingVertices(window, grid, source.uv, region.sourceVertices);
  region.draftSupport = draftSupport(region, source, support.grown(1, grid), [&](int i, int j) {
    const std::uint32_t f = sourceTexture.face[grid.index(i, j)];
    return f != 0 ? int(f) - 1 : sourceLocator.locate(grid.position(i, j)).face;
  });
  result.dabsOutside = dabsPaintingNothing(
      strokes, grid, [&](std::size_t t) { return sourceTexture.face[t] && targetTexture.face[t]; });
  return result;
}

TextureRoiResult textureRoi(const Strokes& strokes, const Parameterization& source,
                            const Parameterization& target, const TextureRoiOptions& options) {
  const auto sourceSide = textureSourceSide(source, options);
  const auto targetSide = textureTargetSide(target, sourceSide->texture.grid, options.kernel);
  const DomainLocator locator(source);
  return copyTexels(strokes, source, target, *sourceSide, *targetSide, locator);
}

}  // namespace geobrush
