#include <memory>
#include <string>

#include "gap_fill.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

class GapFillNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto target = ctx.in<Mesh>("target");
    const auto region = ctx.in<Canvas>("region");
    const auto pasted = ctx.in<Mesh>("pasted");
    const auto feature = ctx.in<Canvas>("feature");
    if (region->source != target && region->source->contentHash() != target->contentHash())
      throw NodeError::input("region", "the region does not lie on this target mesh");
    geobrush::GapFillOptions options;
    options.smoothIterations = int(ctx.param<int>("smooth_iterations"));
    std::shared_ptr<const geobrush::Parameterization> regionMap, placed;
    geobrush::GapDomain domain;
    if (ctx.hasInput("region_map") && ctx.hasInput("placed")) {
      regionMap = ctx.in<geobrush::Parameterization>("region_map");
      placed = ctx.in<geobrush::Parameterization>("placed");
      if (regionMap->canvas != region || regionMap->uv.size() != region->surface.n_vertices())
        throw NodeError::input("region_map", "it does not parameterize the region");
      if (placed->uv.size() != feature->surface.n_vertices())
        throw NodeError::input("placed", "it does not place the feature's vertices");
      domain = {&regionMap->uv, &placed->uv};
    }
    geobrush::GapFillResult result;
    try {
      result =
          geobrush::fillGap(target->surface, *region, pasted->surface, *feature, options, domain);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("pasted", e.what());
    }
    ctx.out("mesh", std::make_shared<const Mesh>(result.mesh));
    ctx.out("map", std::make_shared<const geobrush::PasteMap>(std::move(result.map)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.gap_fill", 1)
            .label("Gap Fill")
            .category("Cut and Paste")
            .doc("Joins a pasted feature to the target: the target region is removed, the gap "
                 "between the feature's loop and the hole's is triangulated by the shortest-edge "
                 "zip (the strip turning over the fewest triangles where the greedy one turns "
                 "some): in the target's domain where both loops' places there are connected "
                 "(as GeoBrush's stitch; a wide gap zipped in space folds), else in space (the "
                 "paper's, turned over against the surface's normals), and rings around the gap "
                 "are smoothed: pass k moves rings 0..k-1 to their neighbours' mean.")
            .input<Mesh>("target", "The target mesh.")
            .input<Canvas>("region", "The target region to replace (geobrush.geodesic_region).")
            .input<Mesh>("pasted", "The feature in place (geobrush.detail_transfer).")
            .input<Canvas>("feature", "The feature canvas the pasted mesh was built from.")
            .optionalInput<geobrush::Parameterization>(
                "region_map",
                "The region's parameterization (intrinsic_param's feature output "
                "on the target): with `placed`, the gap is zipped in this domain.")
            .optionalInput<geobrush::Parameterization>(
                "placed", "The feature's vertices in the target's domain (detail_transfer).")
            .output<Mesh>("mesh", "The target's kept vertices first, then the feature's.")
            .output<geobrush::PasteMap>(
                "map",
                "Target vertices, feature canvas vertices (measure with the feature's "
                "parameterization as the source) and the gap's faces.")
            .paramInt("smooth_iterations", 3, "Ring smoothing passes (the paper's 3).")
            .range(0, 20)
            .node<GapFillNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
