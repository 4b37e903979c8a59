#include <memory>
#include <string>

#include "detail_transfer.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

namespace {

using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;

class DetailTransferNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto encoding = ctx.in<geobrush::DetailEncoding>("encoding");
    const auto feature = ctx.in<Parameterization>("target_feature");
    const auto base = ctx.in<Parameterization>("target_base");
    const auto walk = ctx.in<geobrush::SurfacePath>("walk");
    geobrush::DetailTransferResult result;
    try {
      result = geobrush::transferDetail(*encoding, *feature, *base, *walk);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("walk", e.what());
    }
    if (result.uncovered > 0)
      ctx.warn(std::to_string(result.uncovered) +
               " source base vertices stay outside the target base after shrinking: their "
               "detail is placed over the target base's nearest outline faces");
    if (result.newSelfIntersections > 0)
      ctx.warn(
          "the pasted feature cuts into itself: " + std::to_string(result.newSelfIntersections) +
          " more pairs of its faces meet than at its source; the target bends against the "
          "feature there (a convex feature in a concave region): paste it smaller or "
          "where the target is flatter");
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["new_self_intersections"] = double(result.newSelfIntersections);
    report->values["shrink"] = result.shrink;
    report->values["alignment_residual"] = result.alignmentResidual;
    report->values["uncovered"] = double(result.uncovered);
    auto placed = std::make_shared<Parameterization>();
    placed->canvas = encoding->feature->canvas;
    placed->uv = std::move(result.placedUv);
    placed->normal = encoding->feature->normal;
    placed->origin = feature->origin;
    placed->rotation = feature->rotation;
    placed->scale = feature->scale;
    ctx.out("pasted", std::make_shared<const geobrush::Mesh>(result.pasted));
    ctx.out("placed", placed);
    ctx.out("report", report);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.detail_transfer", 1)
            .label("Detail Transfer")
            .category("Cut and Paste")
            .doc("Forward mapping of cut and paste: the source base is laid onto the target base "
                 "through their domains (aligned by the similarity that takes the source base's "
                 "loop onto the walked loop, shrunk until the target base covers it), then each "
                 "feature vertex is rebuilt at its barycentric point of the moved base face plus "
                 "lambda times its offset in that face's frame (or along the normal, as encoded).")
            .input<geobrush::DetailEncoding>("encoding",
                                             "The feature over the source base "
                                             "(geobrush.detail_encode).")
            .input<Parameterization>("target_feature",
                                     "The target region's parameterization (intrinsic_param).")
            .input<Parameterization>("target_base",
                                     "The target base's parameterization (intrinsic_param).")
            .input<geobrush::SurfacePath>("walk",
                                          "The walked loop (geobrush.geodesic_region): "
                                          "one target point per source base loop vertex.")
            .output<geobrush::Mesh>("pasted",
                                    "The feature with its connectivity, in place on the "
                                    "target (not yet joined to it).")
            .output<Parameterization>("placed",
                                      "The feature's vertices in the target's domain: their "
                                      "source domain points, aligned (for gap_fill to lay the gap "
                                      "out in).")
            .output<geobrush::Metrics>("report",
                                       "shrink (the cover factor), alignment_residual (domain "
                                       "units), uncovered (source base vertices left outside), "
                                       "new_self_intersections (face pairs of the pasted "
                                       "feature that meet, beyond its source's).")
            .node<DetailTransferNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
