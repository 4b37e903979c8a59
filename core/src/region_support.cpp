#include "geobrush/region_support.hpp"

#include <algorithm>
#include <cmath>

namespace geobrush {

NodeWindow NodeWindow::grown(int nodes, const DomainGrid& grid) const {
  return {std::max(0, i0 - nodes), std::min(grid.width - 1, i1 + nodes), std::max(0, j0 - nodes),
          std::min(grid.height - 1, j1 + nodes)};
}

NodeWindow nodesIn(const DomainGrid& grid, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const Eigen::Vector2d a = (lo - grid.origin) / grid.spacing;
  const Eigen::Vector2d b = (hi - grid.origin) / grid.spacing;
  return {std::max(0, int(std::ceil(a.x()))), std::min(grid.width - 1, int(std::floor(b.x()))),
          std::max(0, int(std::ceil(a.y()))), std::min(grid.height - 1, int(std::floor(b.y())))};
}

NodeWindow paintedWindow(const Strokes& strokes, const DomainGrid& grid, Eigen::AlignedBox2d* box) {
  Eigen::AlignedBox2d painted;
  for (const Dab& dab : strokes.dabs) {
    if (dab.subtract) continue;
    const Eigen::Vector2d reach = Eigen::Vector2d::Constant(dab.radius + grid.spacing);
    painted.extend(dab.center - reach);
    painted.extend(dab.center + reach);
  }
  if (box) *box = painted;
  if (painted.isEmpty()) return {};
  return nodesIn(grid, painted.min(), painted.max());
}

std::vector<int> dabsPaintingNothing(const Strokes& strokes, const DomainGrid& grid,
                                     const std::function<bool(std::size_t node)>& covered) {
  std::vector<int> nothing;
  for (std::size_t d = 0; d < strokes.dabs.size(); ++d) {
    const Dab& dab = strokes.dabs[d];
    if (dab.subtract) continue;
    const Eigen::Vector2d reach = Eigen::Vector2d::Constant(dab.radius);
    const NodeWindow disc = nodesIn(grid, dab.center - reach, dab.center + reach);
    bool paints = false;
    for (int j = disc.j0; j <= disc.j1 && !paints; ++j)
      for (int i = disc.i0; i <= disc.i1 && !paints; ++i)
        paints = covered(grid.index(i, j)) &&
                 (grid.position(i, j) - dab.center).squaredNorm() <= dab.radius * dab.radius;
    if (!paints) nothing.push_back(int(d));
  }
  return nothing;
}

BinnedStrokes::BinnedStrokes(const Strokes& strokes, const DomainGrid& grid)
    : strokes_(strokes),
      origin_(grid.origin),
      cellSize_(kCellNodes * grid.spacing),
      columns_((grid.width + kCellNodes - 1) / kCellNodes),
      rows_((grid.height + kCellNodes - 1) / kCellNodes),
      first_(std::size_t(columns_ * rows_) + 1, 0) {
  // Two passes over the dabs' cell ranges: counts, then the dab ids in stroke order.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> filled(first_.begin(), first_.end() - 1);
    for (std::size_t d = 0; d < strokes.dabs.size(); ++d) {
      int c0, c1, r0, r1;
      cellRange(strokes.dabs[d], c0, c1, r0, r1);
      for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) {
          const std::size_t cell = std::size_t(r * columns_ + c);
          if (pass == 0)
            ++first_[cell + 1];
          else
            dabs_[std::size_t(filled[cell]++)] = int(d);
        }
    }
    if (pass == 0) {
      for (std::size_t cell = 1; cell < first_.size(); ++cell)
        first_[cell] += first_[cell - 1];
      dabs_.resize(std::size_t(first_.back()));
    }
  }
}

bool BinnedStrokes::contains(const Eigen::Vector2d& u) const {
  const Eigen::Vector2d g = (u - origin_) / cellSize_;
  const int c = int(std::floor(g.x())), r = int(std::floor(g.y()));
  if (!(c >= 0 && r >= 0 && c < columns_ && r < rows_)) return strokes_.contains(u);
  const std::size_t cell = std::size_t(r * columns_ + c);
  for (int k = first_[cell + 1] - 1; k >= first_[cell]; --k) {
    const Dab& dab = strokes_.dabs[std::size_t(dabs_[std::size_t(k)])];
    if ((u - dab.center).squaredNorm() <= dab.radius * dab.radius) return !dab.subtract;
  }
  return false;
}

void BinnedStrokes::cellRange(const Dab& dab, int& c0, int& c1, int& r0, int& r1) const {
  const Eigen::Vector2d lo = (dab.center - origin_).array() / cellSize_ - dab.radius / cellSize_;
  const Eigen::Vector2d hi = (dab.center - origin_).array() / cellSize_ + dab.radius / cellSize_;
  c0 = std::max(0, int(std::floor(lo.x())) - 1);
  r0 = std::max(0, int(std::floor(lo.y())) - 1);
  c1 = std::min(columns_ - 1, int(std::floor(hi.x())) + 1);
  r1 = std::min(rows_ - 1, int(std::floor(hi.y())) + 1);
}

std::vector<int> draftSupport(const Region2D& region, const Parameterization& source,
                              const NodeWindow& window,
                              const std::function<int(int i, int j)>& faceAt) {
  const DomainGrid& grid = region.grid;
  const NodeWindow reach = window.grown(3, grid);
  std::vector<std::uint8_t> sampled(grid.nodeCount(), 0);
  for (int j = window.j0; j <= window.j1; ++j)
    for (int i = window.i0; i <= window.i1; ++i) {
      if (!region.inside[grid.index(i, j)]) continue;
      for (int dj = -2; dj <= 2; ++dj)
        for (int di = -2 + std::abs(dj); di <= 2 - std::abs(dj); ++di) {
          const int x = i + di, y = j + dj;
          if (x >= 0 && y >= 0 && x < grid.width && y < grid.height) sampled[grid.index(x, y)] = 1;
        }
    }
  std::vector<char> support(source.uv.size(), 0);
  for (int v : region.sourceVertices) {
    support[std::size_t(v)] = 1;
    const Eigen::Vector2d g = (source.uv[std::size_t(v)] - grid.origin) / grid.spacing;
    const int i = int(std::floor(g.x())), j = int(std::floor(g.y()));
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di)
        if (i + di >= 0 && j + dj >= 0 && i + di < grid.width && j + dj < grid.height)
          sampled[grid.index(i + di, j + dj)] = 1;
  }
  const TriMesh& canvas = source.canvas->surface;
  for (int j = reach.j0; j <= reach.j1; ++j)
    for (int i = reach.i0; i <= reach.i1; ++i) {
      if (!sampled[grid.index(i, j)]) continue;
      for (auto v : canvas.fv_range(TriMesh::FaceHandle(faceAt(i, j))))
        support[std::size_t(v.idx())] = 1;
    }
  std::vector<int> vertices;
  for (std::size_t v = 0; v < support.size(); ++v)
    if (support[v]) vertices.push_back(int(v));
  return vertices;
}

}  // namespace geobrush
