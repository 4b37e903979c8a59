// What the nodes that paint a region of interest (geobrush.roi, geobrush.texture_roi) share: the
// painted test of the strokes binned over a grid, and the draft support of a Region2D (GeoBrush
// paper sections 3.2 and 4.4).
#pragma once

#include <Eigen/Geometry>

#include <functional>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

// A rectangle of grid nodes, [i0, i1] x [j0, j1]; empty when i0 > i1 or j0 > j1.
struct NodeWindow {
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  // The window `nodes` wider on every side, clamped to the grid.
  NodeWindow grown(int nodes, const DomainGrid& grid) const;
};

// The grid nodes that may lie in the box [lo, hi], clamped to the grid.
NodeWindow nodesIn(const DomainGrid& grid, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);

// The bounding box of the dabs that add, one grid spacing wider (a margin for rounding at its
// edges), and the grid nodes in it: nothing outside is painted. The window is empty, and `box`
// (where given) left empty, when no dab adds.
NodeWindow paintedWindow(const Strokes& strokes, const DomainGrid& grid,
                         Eigen::AlignedBox2d* box = nullptr);

// The adding dabs, by index in stroke order, that paint no grid node where `covered(node)` holds:
// what a node painting a region warns of.
std::vector<int> dabsPaintingNothing(const Strokes& strokes, const DomainGrid& grid,
                                     const std::function<bool(std::size_t node)>& covered);

// Strokes::contains with the dabs binned over cells of the grid: each query tests only the dabs
// that reach its cell, in stroke order, so the answer is the same and its cost stops growing
// with the length of the stroke. Keeps a reference to the strokes.
class BinnedStrokes {
 public:
  BinnedStrokes(const Strokes& strokes, const DomainGrid& grid);
  bool contains(const Eigen::Vector2d& u) const;

 private:
  static constexpr int kCellNodes = 4;
  // The cells a dab's disc may reach (a cell holds the points within it, its edges included).
  void cellRange(const Dab& dab, int& c0, int& c1, int& r0, int& r1) const;

  const Strokes& strokes_;
  Eigen::Vector2d origin_;
  double cellSize_;
  int columns_, rows_;
  std::vector<int> first_;  // CSR: the dabs of cell k are dabs_[first_[k], first_[k + 1])
  std::vector<int> dabs_;
};

// Region2D::draftSupport: R_in (region.sourceVertices), and the corners of the source faces that
// the membrane's data nodes fall in: every grid node within two nodes (taxicab) of Q, and the
// corners of the cells that hold a vertex of R_in. `window` holds every node of Q and every
// vertex of R_in; what the support reads lies within three nodes of it. `faceAt(i, j)` is the
// source face at grid node (i, j), asked only for the nodes the support reads.
std::vector<int> draftSupport(const Region2D& region, const Parameterization& source,
                              const NodeWindow& window,
                              const std::function<int(int i, int j)>& faceAt);

}  // namespace geobrush
