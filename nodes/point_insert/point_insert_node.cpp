#include <algorithm>

#include "geobrush/border_loop.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "point_insert.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

// delta_min: the param, or where it is 0 the spacing at the border's vertices.
double targetSpacing(const Context& ctx) {
  const double given = ctx.param<double>("delta_min");
  if (given > 0) return given;
  if (!ctx.hasInput("border"))
    throw NodeError::param("delta_min",
                           "0 measures the border's spacing, and no border is connected");
  const auto border = ctx.in<geobrush::BorderLoop>("border");
  if (!border->mesh) throw NodeError::input("border", "the border belongs to no mesh");
  try {
    return geobrush::borderSpacing(border->mesh->surface, border->vertex);
  } catch (const geobrush::PointInsertError& e) {
    throw NodeError::input("border", e.what());
  }
}

class PointInsertNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto input = ctx.in<Mesh>("template");
    geobrush::PointInsertOptions options;
    options.deltaMin = targetSpacing(ctx);
    options.splitBoundary = ctx.param<bool>("split_boundary");
    geobrush::PointInsertResult result;
    try {
      result = geobrush::insertPoints(input->surface, options);
    } catch (const geobrush::PointInsertError& e) {
      throw NodeError::param("delta_min", e.what());
    }
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["delta_min"] = options.deltaMin;
    report->values["inserted"] = double(result.inserted);
    report->values["declined"] = double(result.declined);
    report->values["closest_inserted_spacing"] =
        std::min(result.closestInserted, options.deltaMin) / options.deltaMin;
    ctx.out("template", std::make_shared<const Mesh>(result.mesh));
    ctx.out("report", report);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.point_insert", 1)
            .label("Point Insert")
            .category("Inpainting")
            .doc("Point insertion to the target density (Freeform surface inpainting, section "
                 "5.2): the template's edges longer than sqrt(3) delta_min bisected, longest "
                 "first, a midpoint declined where a vertex lies within delta_min / 2, so every "
                 "point of the template lies within about delta_min of a vertex.")
            .input<Mesh>("template", "The edited template.")
            .optionalInput<geobrush::BorderLoop>(
                "border", "The hole's border: its spacing is delta_min when the param is 0.")
            .output<Mesh>("template", "The template refined; its vertices first, in order.")
            .output<geobrush::Metrics>("report",
                                       "delta_min, vertices inserted and declined, and the least "
                                       "distance from an inserted vertex to another, in units of "
                                       "delta_min (at most 1).")
            .paramDouble("delta_min", 0,
                         "The target spacing; 0: the median length of the edges at the border's "
                         "vertices.")
            .range(0, 1e9)
            .paramBool("split_boundary", false,
                       "Also bisect boundary edges (off: the boundary keeps its vertices, which a "
                       "weld shares with the border).")
            .node<PointInsertNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
