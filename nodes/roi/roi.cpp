#include "roi.hpp"

#include <algorithm>
#include <cmath>

namespace geobrush {
namespace {

struct Box {
  Eigen::Vector2d lo, hi;
};

Box uvBox(const std::vector<Eigen::Vector2d>& uv) {
  Box box{uv.front(), uv.front()};
  for (const auto& u : uv) {
    box.lo = box.lo.cwiseMin(u);
    box.hi = box.hi.cwiseMax(u);
  }
  return box;
}

// Grid indices whose nodes may lie in [lo, hi], clamped to the grid.
void nodeRange(const DomainGrid& grid, const Box& box, int& i0, int& i1, int& j0, int& j1) {
  const Eigen::Vector2d a = (box.lo - grid.origin) / grid.spacing;
  const Eigen::Vector2d b = (box.hi - grid.origin) / grid.spacing;
  i0 = std::max(0, int(std::ceil(a.x())));
  j0 = std::max(0, int(std::ceil(a.y())));
  i1 = std::min(grid.width - 1, int(std::floor(b.x())));
  j1 = std::min(grid.height - 1, int(std::floor(b.y())));
}

// A rectangle of grid nodes, [i0, i1] x [j0, j1]; empty when i0 > i1 or j0 > j1.
struct NodeWindow {
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  NodeWindow grown(int nodes, const DomainGrid& grid) const {
    return {std::max(0, i0 - nodes), std::min(grid.width - 1, i1 + nodes), std::max(0, j0 - nodes),
            std::min(grid.height - 1, j1 + nodes)};
  }
};

// The bounding box of the dabs that add, one grid spacing wider (a margin for rounding at its
// edges), and the grid nodes in it: nothing outside is painted.
NodeWindow paintedWindow(const Strokes& strokes, const DomainGrid& grid, Box& box) {
  bool any = false;
  for (const Dab& dab : strokes.dabs) {
    if (dab.subtract) continue;
    const Eigen::Vector2d reach = Eigen::Vector2d::Constant(dab.radius + grid.spacing);
    box.lo = any ? box.lo.cwiseMin(dab.center - reach) : Eigen::Vector2d(dab.center - reach);
    box.hi = any ? box.hi.cwiseMax(dab.center + reach) : Eigen::Vector2d(dab.center + reach);
    any = true;
  }
  NodeWindow window;
  if (any) nodeRange(grid, box, window.i0, window.i1, window.j0, window.j1);
  return window;
}

// Region2D::draftSupport: R_in, and the corners of the source faces that the membrane's data
// nodes fall in.
// `window`: grid nodes that hold every node of Q and every source vertex of R_in, clamped to the
// grid; what the support reads lies within three nodes of it.
std::vector<int> draftSupport(const Region2D& region, const Parameterization& source,
                              const DomainLocator& locator, std::vector<int>& nodeFace,
                              const NodeWindow& window) {
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
      const std::size_t n = grid.index(i, j);
      if (!sampled[n]) continue;
      if (nodeFace[n] < 0) nodeFace[n] = locator.locate(grid.position(i, j)).face;
      for (auto v : canvas.fv_range(TriMesh::FaceHandle(nodeFace[n])))
        support[std::size_t(v.idx())] = 1;
    }
  std::vector<int> vertices;
  for (std::size_t v = 0; v < support.size(); ++v)
    if (support[v]) vertices.push_back(int(v));
  return vertices;
}

// Crossing-number test: whether u lies inside the closed polygon.
bool insidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& u) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > u.y()) != (b.y() > u.y()) &&
        u.x() < (b.x() - a.x()) * (u.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

// Whether a canvas covers u: a uv triangle holds it, or one of the canvas' holes does.
bool covers(const DomainLocator& locator, const std::vector<std::vector<Eigen::Vector2d>>& holes,
            const Eigen::Vector2d& u) {
  if (locator.locate(u).inside) return true;
  return std::any_of(holes.begin(), holes.end(),
                     [&](const auto& hole) { return insidePolygon(hole, u); });
}

// Strokes::contains with the dabs binned over cells of the grid: each query tests only the dabs
// that reach its cell, in stroke order, so the answer is the same and its cost stops growing
// with the length of the stroke.
class BinnedStrokes {
 public:
  BinnedStrokes(const Strokes& strokes, const DomainGrid& grid)
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

  bool contains(const Eigen::Vector2d& u) const {
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

 private:
  static constexpr int kCellNodes = 4;

  // The cells a dab's disc may reach (a cell holds the points within it, its edges included).
  void cellRange(const Dab& dab, int& c0, int& c1, int& r0, int& r1) const {
    const Eigen::Vector2d lo = (dab.center - origin_).array() / cellSize_ - dab.radius / cellSize_;
    const Eigen::Vector2d hi = (dab.center - origin_).array() / cellSize_ + dab.radius / cellSize_;
    c0 = std::max(0, int(std::floor(lo.x())) - 1);
    r0 = std::max(0, int(std::floor(lo.y())) - 1);
    c1 = std::min(columns_ - 1, int(std::floor(hi.x())) + 1);
    r1 = std::min(rows_ - 1, int(std::floor(hi.y())) + 1);
  }

  const Strokes& strokes_;
  Eigen::Vector2d origin_;
  double cellSize_;
  int columns_, rows_;
  std::vector<int> first_;  // CSR: the dabs of cell k are dabs_[first_[k], first_[k + 1])
  std::vector<int> dabs_;
};

}  // namespace

std::vector<std::vector<Eigen::Vector2d>> canvasHoles(const Parameterization& param) {
  const Canvas& canvas = *param.canvas;
  const TriMesh& mesh = canvas.surface;
  std::vector<char> outer(mesh.n_vertices(), 0);
  for (int v : canvas.boundary)
    outer[std::size_t(v)] = 1;
  std::vector<std::vector<Eigen::Vector2d>> holes;
  std::vector<char> seen(mesh.n_halfedges(), 0);
  for (auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || seen[std::size_t(start.idx())]) continue;
    std::vector<Eigen::Vector2d> polygon;
    bool isOuter = false;
    auto h = start;
    do {
      seen[std::size_t(h.idx())] = 1;
      const int v = mesh.from_vertex_handle(h).idx();
      isOuter = isOuter || outer[std::size_t(v)];
      polygon.push_back(param.uv[std::size_t(v)]);
      h = mesh.next_halfedge_handle(h);
    } while (h != start);
    if (!isOuter && !canvas.boundary.empty()) holes.push_back(std::move(polygon));
  }
  return holes;
}

DomainGrid roiGrid(const Parameterization& source, int resolution) {
  if (resolution < 16) throw RoiError("the grid resolution must be at least 16 nodes");
  if (source.uv.empty()) throw RoiError("the source parameterization has no vertices");
  const Box box = uvBox(source.uv);
  const Eigen::Vector2d extent = box.hi - box.lo;
  if (!(extent.maxCoeff() > 0) || !extent.allFinite())
    throw RoiError("the source domain has no extent");
  DomainGrid grid;
  grid.spacing = extent.maxCoeff() / (resolution - 1 - 2 * kRoiBorder);
  grid.width = int(std::ceil(extent.x() / grid.spacing)) + 1 + 2 * kRoiBorder;
  grid.height = int(std::ceil(extent.y() / grid.spacing)) + 1 + 2 * kRoiBorder;
  grid.origin = box.lo - kRoiBorder * grid.spacing * Eigen::Vector2d::Ones();
  return grid;
}

std::vector<std::uint8_t> domainCoverage(const Parameterization& param, const DomainGrid& grid) {
  std::vector<std::uint8_t> covered(grid.nodeCount(), 0);
  const TriMesh& surface = param.canvas->surface;
  for (auto f : surface.faces()) {
    std::array<Eigen::Vector2d, 3> c;
    int k = 0;
    for (auto v : surface.fv_range(f))
      c[std::size_t(k++)] = param.uv[std::size_t(v.idx())];
    const double area =
        (c[1] - c[0]).x() * (c[2] - c[0]).y() - (c[1] - c[0]).y() * (c[2] - c[0]).x();
    if (area == 0) continue;
    Box box{c[0].cwiseMin(c[1]).cwiseMin(c[2]), c[0].cwiseMax(c[1]).cwiseMax(c[2])};
    int i0, i1, j0, j1;
    nodeRange(grid, box, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Eigen::Vector2d p = grid.position(i, j);
        // Signed areas of the sub-triangles, relative to the face's: all >= 0 inside (either
        // orientation, so that fold-overs count as covering too).
        bool inside = true;
        for (int e = 0; e < 3 && inside; ++e) {
          const Eigen::Vector2d& a = c[std::size_t(e)];
          const Eigen::Vector2d& b = c[std::size_t((e + 1) % 3)];
          const double sub = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
          inside = sub / area >= -1e-12;
        }
        if (inside) covered[grid.index(i, j)] = 1;
      }
  }
  for (const auto& hole : canvasHoles(param)) {
    Box box{hole.front(), hole.front()};
    for (const auto& u : hole) {
      box.lo = box.lo.cwiseMin(u);
      box.hi = box.hi.cwiseMax(u);
    }
    int i0, i1, j0, j1;
    nodeRange(grid, box, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (insidePolygon(hole, grid.position(i, j))) covered[grid.index(i, j)] = 1;
  }
  return covered;
}

std::shared_ptr<const RoiSourceSide> roiSourceSide(const Parameterization& source, int resolution) {
  auto side = std::make_shared<RoiSourceSide>();
  side->grid = roiGrid(source, resolution);
  side->coverage = domainCoverage(source, side->grid);
  side->holes = canvasHoles(source);
  side->nodeFace.assign(side->grid.nodeCount(), -1);
  return side;
}

std::shared_ptr<const RoiTargetSide> roiTargetSide(const Parameterization& source,
                                                   const Parameterization& target,
                                                   const DomainGrid& grid) {
  auto side = std::make_shared<RoiTargetSide>();
  side->coverage = domainCoverage(target, grid);
  side->holes = canvasHoles(target);
  side->sourceCovered.assign(source.uv.size(), -1);
  side->targetCovered.assign(target.uv.size(), -1);
  return side;
}

RoiCoverage roiCoverage(const Parameterization& source, const Parameterization& target,
                        const RoiOptions& options) {
  RoiCoverage coverage;
  coverage.source = roiSourceSide(source, options.resolution);
  coverage.sourceLocator = std::make_shared<const DomainLocator>(source);
  return moveTarget(coverage, source, target);
}

RoiCoverage moveTarget(const RoiCoverage& coverage, const Parameterization& source,
                       const Parameterization& target) {
  RoiCoverage moved = coverage;
  moved.target = roiTargetSide(source, target, coverage.source->grid);
  moved.targetLocator = std::make_shared<const DomainLocator>(target);
  return moved;
}

RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, const RoiCoverage& coverage) {
  const RoiSourceSide& sourceSide = *coverage.source;
  const RoiTargetSide& targetSide = *coverage.target;
  if (sourceSide.nodeFace.size() != sourceSide.grid.nodeCount() ||
      targetSide.sourceCovered.size() != source.uv.size() ||
      targetSide.targetCovered.size() != target.uv.size())
    throw RoiError("the coverage was made for other canvases");
  std::scoped_lock lock(sourceSide.memoLock, targetSide.memoLock);
  RoiResult result;
  Region2D& region = result.region;
  region.grid = sourceSide.grid;
  const DomainGrid& grid = region.grid;
  region.inside.assign(grid.nodeCount(), 0);
  const BinnedStrokes painted(strokes, grid);
  // Only what lies in the box of the adding dabs can be painted: a stroke's cost follows its
  // extent rather than the grid's and the canvases'.
  Box box{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  const NodeWindow window = paintedWindow(strokes, grid, box);
  auto inBox = [&](const Eigen::Vector2d& u) {
    return u.x() >= box.lo.x() && u.y() >= box.lo.y() && u.x() <= box.hi.x() && u.y() <= box.hi.y();
  };
  for (int j = window.j0; j <= window.j1; ++j)
    for (int i = window.i0; i <= window.i1; ++i) {
      const std::size_t n = grid.index(i, j);
      region.inside[n] =
          sourceSide.coverage[n] && targetSide.coverage[n] && painted.contains(grid.position(i, j));
    }

  // The vertices painted whose uv the other canvas covers (asked once per vertex: see RoiMemo).
  auto select = [&](const std::vector<Eigen::Vector2d>& uv, const DomainLocator& other,
                    const std::vector<std::vector<Eigen::Vector2d>>& otherHoles,
                    std::vector<std::int8_t>& covered, std::vector<int>& selected) {
    for (std::size_t v = 0; v < uv.size(); ++v) {
      if (!inBox(uv[v]) || !painted.contains(uv[v])) continue;
      if (covered[v] < 0) covered[v] = covers(other, otherHoles, uv[v]);
      if (covered[v]) selected.push_back(int(v));
    }
  };
  select(source.uv, *coverage.targetLocator, targetSide.holes, targetSide.sourceCovered,
         region.sourceVertices);
  select(target.uv, *coverage.sourceLocator, sourceSide.holes, targetSide.targetCovered,
         region.targetVertices);

  region.draftSupport = draftSupport(region, source, *coverage.sourceLocator, sourceSide.nodeFace,
                                     window.grown(1, grid));

  for (std::size_t d = 0; d < strokes.dabs.size(); ++d) {
    const Dab& dab = strokes.dabs[d];
    if (dab.subtract) continue;
    const Eigen::Vector2d reach = Eigen::Vector2d::Constant(dab.radius);
    int i0, i1, j0, j1;
    nodeRange(grid, {dab.center - reach, dab.center + reach}, i0, i1, j0, j1);
    bool paints = false;
    for (int j = j0; j <= j1 && !paints; ++j)
      for (int i = i0; i <= i1 && !paints; ++i) {
        const std::size_t n = grid.index(i, j);
        paints = sourceSide.coverage[n] && targetSide.coverage[n] &&
                 (grid.position(i, j) - dab.center).squaredNorm() <= dab.radius * dab.radius;
      }
    if (!paints) result.dabsOutside.push_back(int(d));
  }
  return result;
}

RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, const RoiOptions& options) {
  return paintRegion(strokes, source, target, roiCoverage(source, target, options));
}

}  // namespace geobrush
