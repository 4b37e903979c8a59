// The region of interest as a texture copy ("Mesh Geometric Editing Approach Based on GPU Texture",
// section "texture copy"; alternatives spec 1.2, E2/E3): both canvases rasterized into N x N
// textures of (face id + 1, barycentrics) over the shared (u, v) domain, and the painted texels
// covered on both "copied" into the target's. Outputs the same Region2D as geobrush.roi.
//
// The rasterization is exact by construction, so that the CPU twin here and the Vulkan kernel
// (texture_raster_vulkan.hpp) give the same textures bit for bit: uv snapped to fixed point on the
// CPU, integer edge functions with one fill rule for shared edges, and the faces of each tile
// listed by the CPU in depth order, the first that holds a texel winning it.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

class TextureRoiError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

enum class TextureKernel { Cpu, Vulkan };

struct TextureRoiOptions {
  int textureSize = 512;  // N: texels along each side of both textures
  TextureKernel kernel = TextureKernel::Cpu;
};

// Fixed point of the snapped uv: 1/256 texel.
constexpr int kSubtexelBits = 8;
// Texels along a side of the tiles whose face lists the kernel reads (its workgroup's side).
constexpr int kTextureTile = 8;
constexpr int kMinTextureSize = 16;
constexpr int kMaxTextureSize = 4096;
constexpr int kTextureBorder = 4;

// The texels as a grid over the domain: texel (i, j) has its centre at ((i + .5) / N - .5) S,
// ((j + .5) / N - .5) S), centred on uv 0 as E3 centres it, R the source's largest |uv|. [ours]
// The side S spans the source's whole disc of radius R and kTextureBorder texels beyond it on each
// side, S = 2 R N / (N - 2 kTextureBorder): E2's S = sqrt2 R inscribes the texture in the disc and
// cuts the decal's rim off (strokes there would copy nothing that geobrush.roi copies), and the
// membrane's fixed rings need room around the region.
// Throws TextureRoiError for a size outside [kMinTextureSize, kMaxTextureSize] or a source
// domain of zero extent.
DomainGrid textureGrid(const Parameterization& source, int size);

// What both kernels rasterize: a canvas' faces in fixed point, ordered by depth, and per tile the
// faces whose texel box reaches it, in that order.
struct RasterFaces {
  int size = 0;  // N
  int tilesPerSide = 0;
  // Per ordered face: x0, y0, x1, y1, x2, y2 (the corners in 1/2^kSubtexelBits texel, counter-
  // clockwise) and the canvas face id, padded to kFaceInts.
  static constexpr int kFaceInts = 8;
  std::vector<std::int32_t> faces;
  std::vector<std::int32_t> tileStart;  // CSR: tile t lists tileFaces[tileStart[t], [t + 1])
  std::vector<std::int32_t> tileFaces;  // ordered face indices, ascending per tile
  // Per canvas face: twice its snapped area (0 for a face left out: degenerate or outside the
  // texture), and 1 where its corners 1 and 2 were swapped to turn it counter-clockwise.
  std::vector<std::int64_t> doubleArea;
  std::vector<std::uint8_t> flipped;
  std::size_t faceCount() const { return faces.size() / kFaceInts; }
};

// Snaps the canvas' uv to the texture and orders its faces by the height h they keep along the
// canvas' normal n_P: a depth test along -n_P, the highest face winning a texel ("keep the
// fragment with the largest h" [ours]: h is the face's mean (x - origin)·normal of the
// parameterization's frame, ties to the lowest face id). Throws TextureRoiError where a face that
// reaches the texture has a corner too far outside it for 32-bit fixed point.
RasterFaces rasterFaces(const Parameterization& param, const DomainGrid& grid);

// A rasterized canvas: per texel the face holding its centre and the integer edge weights there.
struct CanvasTexture {
  DomainGrid grid;
  std::vector<std::uint32_t> face;  // per texel: canvas face id + 1, 0 where no face holds it
  // Per texel: the edge weights of the rasterized corners 1 and 2 (twice the sub-triangle areas
  // in fixed point squared); zero where no face holds it.
  std::vector<std::int64_t> weight;
  std::vector<std::int64_t> doubleArea;  // per canvas face, as RasterFaces
  std::vector<std::uint8_t> flipped;     // per canvas face, as RasterFaces

  // The barycentric coordinates of texel t's centre in its face, in the order of the face's
  // corners on the canvas mesh; derived from the integer weights, so equal weights give equal
  // coordinates. Zero where no face holds the texel.
  Eigen::Vector3d barycentric(std::size_t texel) const;
};

// The CPU twin of the kernel: the face of each texel and its weights.
void rasterizeCpu(const RasterFaces& faces, std::vector<std::uint32_t>& face,
                  std::vector<std::int64_t>& weight);
// A canvas' texture with the kernel the options ask for (Vulkan throws std::runtime_error
// without a device).
CanvasTexture rasterize(const Parameterization& param, const DomainGrid& grid,
                        TextureKernel kernel);

// What the copy knows of the source canvas alone: its texture and, per face, the texels it holds
// (faces that hold none are judged by the texel under their uv centroid).
struct TextureSourceSide {
  CanvasTexture texture;
  std::vector<int> ownedTexels;     // per source face
  std::vector<int> centroidTexel;   // per source face: the texel under its uv centroid, or -1
  std::vector<int> texellessFaces;  // faces that hold no texel, ascending
};
std::shared_ptr<const TextureSourceSide> textureSourceSide(const Parameterization& source,
                                                           const TextureRoiOptions& options);
std::shared_ptr<const CanvasTexture> textureTargetSide(const Parameterization& target,
                                                       const DomainGrid& grid,
                                                       TextureKernel kernel);

struct TextureRoiResult {
  Region2D region;
  std::vector<int> dabsOutside;  // dabs that paint no texel covered on both textures
};

// The copy: the painted texels covered on both textures (Region2D::inside on the texel grid),
// the corners of the source faces whose texels were all copied (R_in), the target vertices under
// copied texels, and the draft support as geobrush.roi computes it (`sourceLocator` answers for
// grid nodes no source face holds). Texels count as covered where a face holds them: unlike
// roi, the holes of a canvas cover nothing [ours].
TextureRoiResult copyTexels(const Strokes& strokes, const Parameterization& source,
                            const Parameterization& target, const TextureSourceSide& sourceSide,
                            const CanvasTexture& targetTexture, const DomainLocator& sourceLocator);
// Everything from scratch.
TextureRoiResult textureRoi(const Strokes& strokes, const Parameterization& source,
                            const Parameterization& target, const TextureRoiOptions& options = {});

}  // namespace geobrush
