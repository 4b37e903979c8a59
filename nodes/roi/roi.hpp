// The region of interest (GeoBrush paper section 3.2, Fig. 6): the part Q of the shared parameter
// domain painted by the strokes, rasterized on a grid over the source domain, with the vertices it
// selects on both canvases: R_in = {v in P_s : E_s(v) in Q} and the target vertices with E_t in Q
// (the complement of R_out on the target canvas).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

class RoiError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct RoiOptions {
  // Grid nodes along the longer side of the source domain's bounding box, border included.
  int resolution = 256;
};

// Nodes between the source domain's bounding box and the grid's edge: Q stays at least this far
// from the edge, which leaves room for the membrane's two fixed rings (section 4.4).
constexpr int kRoiBorder = 4;

// The grid over E_s(P_s) that the ROI, the membrane and the stitch share. It depends only on the
// source parameterization, so it stays put while the user paints. Throws RoiError for a
// resolution below 16 or a source domain of zero extent.
DomainGrid roiGrid(const Parameterization& source, int resolution);

// The uv polygons of a canvas' inner boundary loops (holes of its mesh, which a fill covers):
// every boundary loop but the outer one.
std::vector<std::vector<Eigen::Vector2d>> canvasHoles(const Parameterization& param);

// Per grid node: 1 where a uv triangle of the parameterization holds it, or one of its holes
// does (the canvas covers it).
std::vector<std::uint8_t> domainCoverage(const Parameterization& param, const DomainGrid& grid);

// What the ROI knows of the source canvas alone: the grid, which of its nodes the canvas covers,
// the canvas' holes, and (a memo, filled as dabs first ask) which source face holds each grid
// node. It stays the same while the strokes change and while the target canvas moves; derived
// data that callers share, so each call reads and fills the memo under its lock.
struct RoiSourceSide {
  DomainGrid grid;
  std::vector<std::uint8_t> coverage;  // per grid node: the source canvas covers it
  std::vector<std::vector<Eigen::Vector2d>> holes;
  mutable std::mutex memoLock;
  mutable std::vector<int> nodeFace;  // per grid node: the source face there, -1 not asked yet
};
// Throws RoiError as roiGrid does.
std::shared_ptr<const RoiSourceSide> roiSourceSide(const Parameterization& source, int resolution);

// What the ROI knows of the target canvas on the source's grid, and (memos) whether the other
// canvas covers a painted vertex's uv, per canvas vertex: -1 not asked yet, 0 or 1.
struct RoiTargetSide {
  std::vector<std::uint8_t> coverage;  // per grid node: the target canvas covers it
  std::vector<std::vector<Eigen::Vector2d>> holes;
  mutable std::mutex memoLock;
  mutable std::vector<std::int8_t> sourceCovered;  // per source canvas vertex
  mutable std::vector<std::int8_t> targetCovered;  // per target canvas vertex
};
std::shared_ptr<const RoiTargetSide> roiTargetSide(const Parameterization& source,
                                                   const Parameterization& target,
                                                   const DomainGrid& grid);

// What stays the same while only the strokes change: both sides and a locator on each
// parameterization (which must outlive them). A dab then locates only where it newly reaches,
// instead of everywhere the strokes reach.
struct RoiCoverage {
  std::shared_ptr<const RoiSourceSide> source;
  std::shared_ptr<const RoiTargetSide> target;
  std::shared_ptr<const DomainLocator> sourceLocator;
  std::shared_ptr<const DomainLocator> targetLocator;
};
RoiCoverage roiCoverage(const Parameterization& source, const Parameterization& target,
                        const RoiOptions& options = {});
// The coverage of the same source and grid with another target canvas, sharing what depends on
// the source alone: dragging the target canvas costs the target canvas' size rather than both.
RoiCoverage moveTarget(const RoiCoverage& coverage, const Parameterization& source,
                       const Parameterization& target);

struct RoiResult {
  Region2D region;
  // Dabs that paint no point covered by both canvases (they change nothing).
  std::vector<int> dabsOutside;
};

// Q = the painted points covered by both canvases. A node of the grid is in Q when the strokes
// paint it and both canvases cover it; a canvas vertex when the strokes paint its uv and the
// other canvas covers that uv (its own covers it by definition). Adds to the coverage's memos.
RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, const RoiCoverage& coverage);
RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, const RoiOptions& options = {});

}  // namespace geobrush
