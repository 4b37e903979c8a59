// geobrush.uv_lines: a canvas with its (u, v) coordinate lines, for display.
#include "geobrush/registry.hpp"
#include "uv_lines.hpp"

namespace geobrush {
namespace {

void uvLines(Context& ctx) {
  UvLinesOptions options;
  options.spacing = ctx.param<double>("spacing");
  options.width = ctx.param<double>("width");
  try {
    UvLinesResult result = paintUvLines(*ctx.in<Parameterization>("parameterization"), options);
    ctx.out("mesh", std::make_shared<const Mesh>(std::move(result.mesh)));
  } catch (const std::invalid_argument& e) {
    throw NodeError::input("parameterization", e.what());
  }
}

void registerNodes(PluginRegistrar& registrar) {
  registrar.add(NodeTypeBuilder("geobrush.uv_lines", 1)
                    .label("UV lines")
                    .category("Display")
                    .doc("Paints a canvas' (u, v) coordinate lines as vertex colours: u lines "
                         "red, v lines blue, as the GeoBrush interface shows canvases.")
                    .input<Parameterization>("parameterization", "The canvas and its map.")
                    .output<Mesh>("mesh", "The canvas surface with one colour per vertex.")
                    .paramDouble("spacing", 0.0,
                                 "Domain distance between lines; 0 picks a tenth of the domain.")
                    .range(0.0, 1e9)
                    .paramDouble("width", 0.15, "Line width as a fraction of the spacing.")
                    .range(0.01, 0.99)
                    .compute(uvLines)
                    .build());
}

}  // namespace
}  // namespace geobrush

GEOBRUSH_PLUGIN(geobrush::registerNodes)
