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

// Painting changes only the strokes: the node keeps the grid, the canvases' coverage and their
// locators for as long as both parameterizations and the resolution stay the same. Dragging the
// target canvas changes only the target's: the source's are kept.
class RoiNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto strokes = ctx.in<Strokes>("strokes");
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    geobrush::RoiOptions options;
    options.resolution = ctx.param<int>("resolution");
    try {
      if (!coverage_ || source != source_ || options.resolution != resolution_) {
        coverage_.reset();
        coverage_ = std::make_unique<geobrush::RoiCoverage>(
            geobrush::roiCoverage(*source, *target, options));
        source_ = source;
        target_ = target;
        resolution_ = options.resolution;
      } else if (target != target_) {
        try {
          geobrush::moveTarget(*coverage_, *target);
        } catch (...) {
          coverage_.reset();  // half moved
          throw;
        }
        target_ = target;
      }
    } catch (const geobrush::RoiError& e) {
      throw NodeError::input("source", e.what());
    }
    geobrush::RoiResult result = geobrush::paintRegion(*strokes, *source, *target, *coverage_);
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

 private:
  std::unique_ptr<geobrush::RoiCoverage> coverage_;
  std::shared_ptr<const Parameterization> source_, target_;
  int resolution_ = 0;
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
