#include <memory>
#include <stdexcept>

#include "additive_draft.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

namespace {

using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;

class AdditiveDraftNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    geobrush::AdditiveDraftOptions options;
    options.gain = ctx.param<double>("gain");
    geobrush::AdditiveDraft result;
    try {
      result = geobrush::additiveDraft(*source, *target, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("source", e.what());
    }
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["largest_detail"] = result.largestDetail;
    ctx.out("draft", std::make_shared<const Mesh>(result.draft));
    ctx.out("base", std::make_shared<const Mesh>(result.base));
    ctx.out("report", report);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.additive_draft", 1)
            .label("Additive Draft")
            .category("Paste")
            .doc("A draft that adds the source's detail to the target instead of replacing the "
                 "target's (the GeoBrush paper's future work): each source canvas vertex goes "
                 "to the target's surface under its (u, v) plus its offset from the source "
                 "canvas' smooth base (the canvas smoothed to rest over its loop), carried from "
                 "the base's frame into the target's and scaled by the paste's scale. Wired in "
                 "place of gc_warp's draft, the membrane and the stitch paste it as usual: no "
                 "cage is needed.")
            .input<Parameterization>("source", "E_s: the source canvas and its (u, v).")
            .input<Parameterization>("target", "E_t: the target canvas in the same domain.")
            .output<Mesh>("draft",
                          "The source canvas surface, moved (what membrane and stitch "
                          "read as the draft).")
            .output<Mesh>("base", "The source canvas' smooth base, the detail's reference.")
            .output<geobrush::Metrics>("report",
                                       "largest_detail: the longest offset from the "
                                       "base, in source units.")
            .paramDouble("gain", 1.0, "Multiplies the source's detail (0: the target's surface).")
            .range(-100.0, 100.0)
            .node<AdditiveDraftNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
