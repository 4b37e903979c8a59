#include <memory>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "strokes.hpp"

namespace {

using geobrush::Context;
using geobrush::NodeError;
using geobrush::Strokes;

class StrokesNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    try {
      ctx.out("strokes", std::make_shared<const Strokes>(
                             geobrush::strokesFromRows(ctx.param<std::vector<double>>("dabs"))));
    } catch (const geobrush::StrokesError& e) {
      throw NodeError::param("dabs", e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.strokes", 1)
            .label("Strokes")
            .category("Real-time")
            .doc("The brush dabs painted in the shared parameter domain (paper section 3.2), in "
                 "painting order: each adds its disc to the region of interest or subtracts it. "
                 "Saved in the graph, so a painted session replays headless.")
            .output<Strokes>("strokes", "The dabs, in order.")
            .paramList("dabs", geobrush::kDabRowSize, {},
                       "Dabs as rows of u, v, radius, mode (1 adds, -1 subtracts), in the source "
                       "canvas' parameter domain.")
            .node<StrokesNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
