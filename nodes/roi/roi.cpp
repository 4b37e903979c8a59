#include "roi.hpp"

#include <algorithm>
#include <cmath>

#include "geobrush/region_support.hpp"

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
    const NodeWindow nodes = nodesIn(grid, box.lo, box.hi);
    for (int j = nodes.j0; j <= nodes.j1; ++j)
      for (int i = nodes.i0; i <= nodes.i1; ++i) {
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
    const NodeWindow nodes = nodesIn(grid, box.lo, box.hi);
    for (int j = nodes.j0; j <= nodes.j1; ++j)
      for (int i = nodes.i0; i <= nodes.i1; ++i)
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
  Eigen::AlignedBox2d box;
  const NodeWindow window = paintedWindow(strokes, grid, &box);
  auto inBox = [&](const Eigen::Vector2d& u) { return box.contains(u); };
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

  // The source face at a node is asked once per source side (a memo shared by later dabs).
  std::vector<int>& nodeFace = sourceSide.nodeFace;
  const DomainLocator& sourceLocator = *coverage.sourceLocator;
  region.draftSupport = draftSupport(region, source, window.grown(1, grid), [&](int i, int j) {
    const std::size_t n = grid.index(i, j);
    if (nodeFace[n] < 0) nodeFace[n] = sourceLocator.locate(grid.position(i, j)).face;
    return nodeFace[n];
  });

  result.dabsOutside = dabsPaintingNothing(strokes, grid, [&](std::size_t n) {
    return sourceSide.coverage[n] && targetSide.coverage[n];
  });
  return result;
}

RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, const RoiOptions& options) {
  return paintRegion(strokes, source, target, roiCoverage(source, target, options));
}

}  // namespace geobrush
