// Triangulating the strip between two closed loops: the seam between a paste and the hole it
// fills (GeoBrush's stitch, section 4.4, in the parameter domain; the cut-and-paste gap fill in
// space, after Barequet and Sharir).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

namespace geobrush {

// A corner of a strip triangle: a position in loop a or in loop b.
struct LoopCorner {
  bool onA = true;
  std::size_t index = 0;
};

// What the zip measures: the length of a new edge between a[i] and b[j], and whether a triangle
// turns over (its orientation disagrees with both sides').
class LoopZipMetric {
 public:
  virtual ~LoopZipMetric() = default;
  virtual double edge(std::size_t i, std::size_t j) const = 0;
  virtual bool turnsOver(LoopCorner p, LoopCorner q, LoopCorner r) const = 0;
  // Whether the triangle has no area to speak of (its corners in a line, to rounding): zipChains
  // avoids such triangles, which a gap between chains lying on one line would otherwise get.
  virtual bool flat(LoopCorner, LoopCorner, LoopCorner) const { return false; }
};

// Loops laid out in a parameter domain whose faces are counterclockwise: edges measured there,
// a triangle turned over when clockwise.
class DomainZipMetric final : public LoopZipMetric {
 public:
  DomainZipMetric(const std::vector<Eigen::Vector2d>& uvA, const std::vector<Eigen::Vector2d>& uvB)
      : uvA_(uvA), uvB_(uvB) {}
  double edge(std::size_t i, std::size_t j) const override { return (uvA_[i] - uvB_[j]).norm(); }
  bool turnsOver(LoopCorner p, LoopCorner q, LoopCorner r) const override;
  bool flat(LoopCorner p, LoopCorner q, LoopCorner r) const override;

 private:
  const Eigen::Vector2d& at(LoopCorner c) const { return c.onA ? uvA_[c.index] : uvB_[c.index]; }
  const std::vector<Eigen::Vector2d>& uvA_;
  const std::vector<Eigen::Vector2d>& uvB_;
};

// Loops in space: edges measured in 3D, a triangle turned over when its normal points against
// the mean of its corners' reference normals (the surface's normals there).
class SpaceZipMetric final : public LoopZipMetric {
 public:
  SpaceZipMetric(const std::vector<Eigen::Vector3d>& pointsA,
                 const std::vector<Eigen::Vector3d>& pointsB,
                 const std::vector<Eigen::Vector3d>& normalsA,
                 const std::vector<Eigen::Vector3d>& normalsB)
      : pointsA_(pointsA), pointsB_(pointsB), normalsA_(normalsA), normalsB_(normalsB) {}
  double edge(std::size_t i, std::size_t j) const override {
    return (pointsA_[i] - pointsB_[j]).norm();
  }
  bool turnsOver(LoopCorner p, LoopCorner q, LoopCorner r) const override;
  bool flat(LoopCorner p, LoopCorner q, LoopCorner r) const override;

 private:
  const Eigen::Vector3d& pointAt(LoopCorner c) const {
    return c.onA ? pointsA_[c.index] : pointsB_[c.index];
  }
  const std::vector<Eigen::Vector3d>& pointsA_;
  const std::vector<Eigen::Vector3d>& pointsB_;
  const std::vector<Eigen::Vector3d>& normalsA_;
  const std::vector<Eigen::Vector3d>& normalsB_;
};

// The triangles between loop `a` and loop `b` (vertex ids; the metric sees positions in the
// loops), both in the direction of their boundary halfedges, starting at the vertex of b nearest
// a[0]: each triangle takes the next vertex of one loop and the current vertex of the other, so
// its orientation agrees with both sides. The greedy strip takes the shorter new edge at each step
// (with `keepOrientation`, the other one where only the other keeps the triangle from turning
// over); where it turns triangles over, the strip that turns over the fewest and of those has
// the shortest new edges (Fuchs, Kedem and Uselton 1977) when the loops' product is small enough.
// Gives |a| + |b| triangles.
std::vector<std::array<int, 3>> zipLoops(const std::vector<int>& a, const std::vector<int>& b,
                                         const LoopZipMetric& metric, bool keepOrientation);

// The triangles filling the polygon between two open chains with common ends: `a` runs from
// a.front() to a.back(), `b` from b.front() == a.back() to b.back() == a.front(), both in the
// direction of their boundary halfedges (the gap between two loops that share vertices, between
// two consecutive shared ones; with one shared vertex, both chains are whole loops from it back
// to it). The zip walks a forwards and b backwards from their common vertex a.front() to a.back(),
// each triangle taking the next vertex of one chain and the current vertex of the other, so its
// orientation agrees with both sides; the first and last steps join a vertex to itself and give
// no triangle, and no new edge joins a vertex to itself. It takes the shorter new edge at each
// step (with `keepOrientation`, the other one where only the other keeps the triangle from
// turning over or lying flat); where the greedy strip turns over or flattens triangles, the strip
// with the fewest such and of those the shortest new edges, when the chains' product is small
// enough. Gives |a| + |b| - 4 triangles: none for two chains of one edge each (one shared edge).
// Throws std::invalid_argument when a chain has fewer than two vertices or the ends differ.
std::vector<std::array<int, 3>> zipChains(const std::vector<int>& a, const std::vector<int>& b,
                                          const LoopZipMetric& metric, bool keepOrientation);

}  // namespace geobrush
