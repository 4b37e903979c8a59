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
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["shrink"] = result.shrink;
    report->values["alignment_residual"] = result.alignmentResidual;
    report->values["uncovered"] = double(result.uncovered);
    ctx.out("pasted", std::make_shared<const geobrush::Mesh>(result.pasted));
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
            .output<geobrush::Metrics>("report",
                                       "shrink (the cover factor), alignment_residual (domain "
                                       "units), uncovered (source base vertices left outside).")
            .node<DetailTransferNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
