#include "geobrush/region.hpp"

#include <algorithm>

#include <cmath>
#include <span>
#include <stdexcept>
#include <string>

#include "geobrush/canvas.hpp"

namespace geobrush {
namespace {

void hashGrid(Hasher& hasher, const DomainGrid& grid) {
  hasher.f64(grid.origin.x()).f64(grid.origin.y()).f64(grid.spacing);
  hasher.u64(std::uint64_t(grid.width)).u64(std::uint64_t(grid.height));
}

std::string gridText(const DomainGrid& grid) {
  std::string text = std::to_string(grid.width);
  text += " x ";
  text += std::to_string(grid.height);
  text += " grid";
  return text;
}

}  // namespace

Hash Strokes::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(dabs.size());
  for (const Dab& dab : dabs)
    hasher.f64(dab.center.x()).f64(dab.center.y()).f64(dab.radius).u64(dab.subtract);
  return hasher.digest();
}

std::string Strokes::summary() const {
  std::string text = "strokes: ";
  text += std::to_string(dabs.size());
  text += " dabs";
  return text;
}

bool Strokes::contains(const Eigen::Vector2d& u) const {
  for (auto dab = dabs.rbegin(); dab != dabs.rend(); ++dab)
    if ((u - dab->center).squaredNorm() <= dab->radius * dab->radius) return !dab->subtract;
  return false;
}

Hash Region2D::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId);
  hashGrid(hasher, grid);
  hasher.span(std::span<const std::uint8_t>(inside));
  hasher.span(std::span<const int>(sourceVertices));
  hasher.span(std::span<const int>(targetVertices));
  hasher.span(std::span<const int>(draftSupport));
  return hasher.digest();
}

void requireRegionOn(const Region2D& region, std::size_t sourceCanvasVertices,
                     const std::size_t* targetCanvasVertices) {
  // The lists ascend: their last entries are their largest.
  const auto require = [](const std::vector<int>& vertices, std::size_t count, const char* side) {
    if (vertices.empty() || (vertices.front() >= 0 && std::size_t(vertices.back()) < count)) return;
    const int named = vertices.front() < 0 ? vertices.front() : vertices.back();
    throw std::invalid_argument("the region names " + std::string(side) + " canvas vertex " +
                                std::to_string(named) + ", which this " + std::to_string(count) +
                                "-vertex canvas does not have: it was painted on other canvases "
                                "(connect the ones its ROI was painted on)");
  };
  require(region.sourceVertices, sourceCanvasVertices, "source");
  require(region.draftSupport, sourceCanvasVertices, "source");
  if (targetCanvasVertices) require(region.targetVertices, *targetCanvasVertices, "target");
}

std::string Region2D::summary() const {
  std::size_t nodes = 0;
  for (auto in : inside)
    nodes += in;
  std::string text = "region: ";
  text += std::to_string(nodes);
  text += " nodes of a ";
  text += gridText(grid);
  text += ", ";
  text += std::to_string(sourceVertices.size());
  text += " source and ";
  text += std::to_string(targetVertices.size());
  text += " target vertices";
  return text;
}

Hash Field2D::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId);
  hashGrid(hasher, grid);
  hasher.u64(values.size());
  for (const auto& v : values)
    hasher.f64(v.x()).f64(v.y()).f64(v.z());
  hasher.span(std::span<const std::uint8_t>(defined));
  return hasher.digest();
}

std::string Field2D::summary() const {
  std::string text = "field on a ";
  text += gridText(grid);
  return text;
}

Hash PasteMap::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId);
  hasher.span(std::span<const int>(targetVertex));
  hasher.span(std::span<const int>(sourceVertex));
  hasher.span(std::span<const int>(seamFaces));
  return hasher.digest();
}

std::string PasteMap::summary() const {
  const auto pasted =
      std::count_if(sourceVertex.begin(), sourceVertex.end(), [](int v) { return v >= 0; });
  std::string text = std::to_string(pasted);
  text += " pasted of ";
  text += std::to_string(sourceVertex.size());
  text += " vertices, ";
  text += std::to_string(seamFaces.size());
  text += " seam faces";
  return text;
}

bool Field2D::sample(const Eigen::Vector2d& u, Eigen::Vector3d& value) const {
  const Eigen::Vector2d g = (u - grid.origin) / grid.spacing;
  const double fi = std::floor(g.x()), fj = std::floor(g.y());
  if (!(fi >= 0 && fj >= 0 && fi + 1 < grid.width && fj + 1 < grid.height)) return false;
  const int i = int(fi), j = int(fj);
  const double s = g.x() - fi, t = g.y() - fj;
  const std::size_t corners[4] = {grid.index(i, j), grid.index(i + 1, j), grid.index(i, j + 1),
                                  grid.index(i + 1, j + 1)};
  for (std::size_t c : corners)
    if (!defined[c]) return false;
  value = (1 - t) * ((1 - s) * values[corners[0]] + s * values[corners[1]]) +
          t * ((1 - s) * values[corners[2]] + s * values[corners[3]]);
  return true;
}

std::vector<int> targetMeshVertices(const Region2D& region, const Parameterization& target) {
  const std::vector<int>& toMesh = target.canvas->sourceVertex;
  std::vector<int> vertices;
  vertices.reserve(region.targetVertices.size());
  for (int v : region.targetVertices) {
    if (v < 0 || std::size_t(v) >= toMesh.size())
      throw std::invalid_argument("the region covers target canvas vertex " + std::to_string(v) +
                                  ", which the target's canvas (" + std::to_string(toMesh.size()) +
                                  " vertices) does not have");
    vertices.push_back(toMesh[std::size_t(v)]);
  }
  std::sort(vertices.begin(), vertices.end());
  return vertices;
}

}  // namespace geobrush
