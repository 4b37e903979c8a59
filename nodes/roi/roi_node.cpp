#include <memory>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "roi.hpp"

namespace {

using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Region2D;
using geobrush::Strokes;

std::string dabList(const std::vector<int>& dabs) {
  std::string text;
  for (std::size_t k = 0; k < dabs.size() && k < 5; ++k) {
    if (k > 0) text += ", ";
    text += std::to_string(dabs[k] + 1);
  }
  if (dabs.size() > 5) text += ", ...";
  return text;
}

// Painting changes only the strokes: the grid, both canvases' coverage of it and their locators
// are derived data, kept by the framework while the parameterizations and the resolution stay
// the same; dragging the target canvas changes only the target's side. The locators are the
// ones the membrane asks for on the same canvases.
class RoiNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto strokes = ctx.in<Strokes>("strokes");
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    const int resolution = ctx.param<int>("resolution");
    const geobrush::Hash resolutionKey = geobrush::Hasher().u64(std::uint64_t(resolution)).digest();
    geobrush::RoiCoverage coverage;
    try {
      coverage.source = ctx.derived("roi_source_side", {"source"}, resolutionKey,
                                    [&] { return geobrush::roiSourceSide(*source, resolution); });
      coverage.target = ctx.derived("roi_target_side", {"source", "target"}, resolutionKey, [&] {
        return geobrush::roiTargetSide(*source, *target, coverage.source->grid);
      });
    } catch (const geobrush::RoiError& e) {
      throw NodeError::input("source", e.what());
    }
    coverage.sourceLocator = geobrush::derivedLocator(ctx, "source");
    coverage.targetLocator = geobrush::derivedLocator(ctx, "target");
    geobrush::RoiResult result = geobrush::paintRegion(*strokes, *source, *target, coverage);
    if (!result.dabsOutside.empty()) {
      std::string message = std::to_string(result.dabsOutside.size());
      message += " dabs (";
      message += dabList(result.dabsOutside);
      message += ") paint no point that both canvases cover; they change nothing";
      ctx.warn(message);
    }
    if (result.region.empty() && !strokes->dabs.empty())
      ctx.warn("the strokes select no source vertex: the target stays unchanged");
    ctx.out("region", std::make_shared<const Region2D>(std::move(result.region)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.roi", 1)
          .label("Region of Interest")
          .category("Real-time")
          .doc("The region Q of the shared parameter domain painted by the strokes and covered "
               "by both canvases (paper section 3.2), rasterized on a grid over the source "
               "domain, with R_in (source canvas vertices in Q) and the target canvas vertices "
               "in Q, which the paste replaces.")
          .input<Strokes>("strokes", "The dabs painted so far.")
          .input<Parameterization>("source", "E_s: the source canvas and its map.")
          .input<Parameterization>("target", "E_t: the target canvas in the same domain.")
          .output<Region2D>("region", "Q on its grid, R_in and the covered target vertices.")
          .paramInt("resolution", 256,
                    "Grid nodes along the longer side of the source domain (the membrane's grid).")
          .range(16, 4096)
          .node<RoiNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
