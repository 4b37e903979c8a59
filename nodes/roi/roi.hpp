// The region of interest (GeoBrush paper section 3.2, Fig. 6): the part Q of the shared parameter
// domain painted by the strokes, rasterized on a grid over the source domain, with the vertices it
// selects on both canvases: R_in = {v in P_s : E_s(v) in Q} and the target vertices with E_t in Q
// (the complement of R_out on the target canvas).
#pragma once

#include <cstdint>
#include <memory>
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

// The locator's answers that every dab asks again (whether the other canvas covers a vertex's
// uv, which source face holds a grid node), kept as they are first asked: a dab then locates
// only where it newly reaches, instead of everywhere the strokes reach.
struct RoiMemo {
  std::vector<std::int8_t> sourceCovered;  // per source canvas vertex: -1 not asked yet, 0 or 1
  std::vector<std::int8_t> targetCovered;  // per target canvas vertex: -1 not asked yet, 0 or 1
  std::vector<int> nodeFace;               // per grid node: the source face there, -1 not asked
};

// What stays the same while only the strokes change: the grid, both canvases' coverage of its
// nodes, a locator on each parameterization, and what the locators answered so far. The
// locators refer to the parameterizations, which must outlive it.
struct RoiCoverage {
  DomainGrid grid;
  std::vector<std::uint8_t> source;
  std::vector<std::uint8_t> target;
  std::shared_ptr<const DomainLocator> sourceLocator;
  std::shared_ptr<const DomainLocator> targetLocator;
  std::vector<std::vector<Eigen::Vector2d>> sourceHoles, targetHoles;
  RoiMemo memo;
};
RoiCoverage roiCoverage(const Parameterization& source, const Parameterization& target,
                        const RoiOptions& options = {});
// Makes `coverage` the coverage of the same source and grid with another target canvas, keeping
// what depends on the source alone (its coverage, locator and holes, and which source face holds
// each grid node): dragging the target canvas costs the target canvas' size rather than both.
void moveTarget(RoiCoverage& coverage, const Parameterization& target);

struct RoiResult {
  Region2D region;
  // Dabs that paint no point covered by both canvases (they change nothing).
  std::vector<int> dabsOutside;
};

// Q = the painted points covered by both canvases. A node of the grid is in Q when the strokes
// paint it and both canvases cover it; a canvas vertex when the strokes paint its uv and the
// other canvas covers that uv (its own covers it by definition). Adds to the coverage's memo: one
// call at a time per coverage.
RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, RoiCoverage& coverage);
RoiResult paintRegion(const Strokes& strokes, const Parameterization& source,
                      const Parameterization& target, const RoiOptions& options = {});

}  // namespace geobrush
