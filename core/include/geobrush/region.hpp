// Values of the GeoBrush real-time stage (paper sections 3.2, 4.4): brush strokes in the shared
// parameter domain, the region of interest Q they paint, and fields on a regular grid over it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "geobrush/value.hpp"

namespace geobrush {

class Parameterization;

// One brush dab in the parameter domain: a disc that adds to Q or, subtracting, removes from it.
struct Dab {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0;
  bool subtract = false;
  bool operator==(const Dab&) const = default;
};

// The dabs painted so far, in painting order: a later dab overrides the earlier ones where they
// overlap, as a paint brush and an eraser do.
class Strokes final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Strokes";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  // Whether u is painted: inside the last dab that covers it, that dab adding.
  bool contains(const Eigen::Vector2d& u) const;

  std::vector<Dab> dabs;
};
using StrokesPtr = std::shared_ptr<const Strokes>;

// A regular grid of nodes over the parameter domain: node (i, j), 0 <= i < width,
// 0 <= j < height, sits at origin + spacing (i, j) and is stored at index j * width + i.
struct DomainGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double spacing = 1;
  int width = 0;
  int height = 0;

  std::size_t nodeCount() const { return std::size_t(width) * std::size_t(height); }
  std::size_t index(int i, int j) const { return std::size_t(j) * std::size_t(width) + i; }
  Eigen::Vector2d position(int i, int j) const { return origin + spacing * Eigen::Vector2d(i, j); }
  bool operator==(const DomainGrid&) const = default;
};

// The region of interest Q (paper section 3.2) rasterized on a grid, with the canvas vertices it
// selects: R_in on the source canvas, and on the target canvas the vertices it covers (the
// complement of R_out there).
class Region2D final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Region2D";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  bool empty() const { return sourceVertices.empty(); }

  DomainGrid grid;
  std::vector<std::uint8_t> inside;  // per grid node: 1 in Q
  std::vector<int> sourceVertices;   // R_in: source canvas vertices u with E_s(u) in Q, ascending
  std::vector<int> targetVertices;   // target canvas vertices with E_t in Q, ascending
  // The source canvas vertices whose warped positions G(v) a paste of Q reads, ascending: R_in and
  // the corners of the source faces under every grid node within two nodes (taxicab) of Q or at
  // a corner of a cell that holds a vertex of R_in (where the membrane samples g_in).
  std::vector<int> draftSupport;
};
using Region2DPtr = std::shared_ptr<const Region2D>;

// Throws std::invalid_argument unless every vertex the region names lies on canvases of these
// sizes (the target's unchecked where null): a region painted on other canvases than the ones a
// node is given would index vertices they do not have.
void requireRegionOn(const Region2D& region, std::size_t sourceCanvasVertices,
                     const std::size_t* targetCanvasVertices = nullptr);

// A function from the parameter domain to R^3 sampled at the nodes of a grid, e.g. the offset
// membrane x~ of Eq. 4. Nodes it does not define hold zero and are marked so.
class Field2D final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Field2D";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  // Bilinear interpolation at u; nodes outside the grid count as undefined. Returns false where
  // one of the four nodes around u is undefined.
  bool sample(const Eigen::Vector2d& u, Eigen::Vector3d& value) const;

  DomainGrid grid;
  std::vector<Eigen::Vector3d> values;  // per grid node
  std::vector<std::uint8_t> defined;    // per grid node: 1 where values holds the field
};
using Field2DPtr = std::shared_ptr<const Field2D>;

// Where each vertex of a pasted mesh came from, and which faces join the paste to the target:
// what lets geobrush.metrics tell the seam, the pasted detail and the untouched target apart.
class PasteMap final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.PasteMap";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  std::vector<int> targetVertex;  // result vertex -> target mesh vertex, or -1
  std::vector<int> sourceVertex;  // result vertex -> source canvas vertex, or -1
  std::vector<int> seamFaces;     // result faces of the strips between the two outlines
};
using PasteMapPtr = std::shared_ptr<const PasteMap>;

// The vertices of the target canvas' mesh that Q covers (region.targetVertices through the
// canvas' sourceVertex), ascending. Throws std::invalid_argument when the region names a vertex
// the target's canvas does not have (a region painted over another target).
std::vector<int> targetMeshVertices(const Region2D& region, const Parameterization& target);

}  // namespace geobrush
