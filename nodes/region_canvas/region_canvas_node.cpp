#include <memory>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "region_canvas.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Strokes;

class RegionCanvasNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto strokes = ctx.in<Strokes>("strokes");
    const auto source = ctx.in<Parameterization>("source");
    geobrush::RegionCanvasResult result;
    try {
      result = geobrush::regionCanvas(*strokes, *source);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("strokes", e.what());
    }
    if (result.dropped > 0)
      ctx.warn(std::to_string(result.dropped) +
               " faces of the region are left out: they touch the rest at a corner only or form "
               "another piece");
    ctx.out("feature", std::make_shared<const Canvas>(std::move(result.feature)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.region_canvas", 1)
            .label("Region Canvas")
            .category("Cut and Paste")
            .doc("The painted region as a canvas of its own (the feature F of cut and paste): "
                 "the source canvas faces whose three corners the strokes paint, as one piece "
                 "bounded by one loop. Faces that touch the rest at a corner only and pieces "
                 "apart from the one under the origin are left out (with a warning); holes the "
                 "region surrounds are filled, so a painted ring takes in what it encloses. Any "
                 "genus inside.")
            .input<Strokes>("strokes",
                            "The painting in the shared (u, v) domain (geobrush.strokes, or "
                            "roi_correct's corrected strokes).")
            .input<Parameterization>("source",
                                     "The source canvas' parameterization the region "
                                     "was painted on.")
            .output<Canvas>("feature", "The feature F, on the source mesh.")
            .node<RegionCanvasNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
