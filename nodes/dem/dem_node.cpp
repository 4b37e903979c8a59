#include <memory>
#include <numbers>

#include "dem.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;

// Dragging the target canvas re-evaluates this node on the same target mesh: its PreparedTarget
// (normals, nearest-point search) is derived data the framework keeps.
class DemNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto source = ctx.in<Parameterization>("source");
    geobrush::TargetDemOptions options;
    const auto origin = ctx.param<geobrush::Vec3>("origin");
    options.origin = {origin[0], origin[1], origin[2]};
    options.angleDegrees = ctx.param<double>("angle");
    options.scale = ctx.param<double>("scale");
    options.margin = ctx.param<double>("margin");
    options.keepHoles = ctx.param<bool>("keep_holes");
    if (ctx.hasInput("source_cage"))
      for (const auto& column : ctx.in<geobrush::Cage>("source_cage")->domain)
        options.preferredRadius = std::max(options.preferredRadius, column.norm());
    try {
      const auto target = ctx.derived("dem_prepared_target", {"mesh"}, 0, [&] {
        return std::make_shared<const geobrush::PreparedTarget>(mesh);
      });
      geobrush::TargetDemResult dem = geobrush::targetExponentialMap(*target, source->uv, options);
      auto out = std::make_shared<Parameterization>();
      out->canvas = std::make_shared<const geobrush::Canvas>(std::move(dem.canvas));
      out->uv = std::move(dem.uv);
      out->normal = std::move(dem.normal);
      out->origin = dem.origin;
      out->rotation = options.angleDegrees * std::numbers::pi / 180;
      out->scale = options.scale;
      ctx.out("parameterization", std::move(out));
    } catch (const geobrush::TargetDemError& e) {
      if (e.option() == "mesh" || e.option() == "source")
        throw NodeError::input(e.option(), e.what());
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.dem", 1)
            .label("Target DEM")
            .category("Parameterization")
            .doc("Grows the target canvas P_t and its map E_t together (paper section 4.2, last "
                 "paragraph): the original discrete exponential map (surface normals, steps "
                 "rescaled to their length) fixed vertex by vertex in order of distance from "
                 "the origin, until the region's uv image holds E_s(P_s) plus the margin. uv are "
                 "in the domain shared with the source: target distances divided by the scale, "
                 "axes turned by the angle.")
            .input<Mesh>("mesh", "The target surface.")
            .input<Parameterization>("source",
                                     "E_s of the source canvas: the domain region to cover.")
            .optionalInput<geobrush::Cage>(
                "source_cage",
                "The source cage: the canvas also covers its columns where the target allows "
                "(not wrapping around it or taking in a hole), so that the target cage fits each.")
            .output<Parameterization>("parameterization",
                                      "The target canvas with uv in the shared domain, surface "
                                      "normals, the origin frame, rotation and scale.")
            .paramVec3("origin", {0, 0, 0},
                       "The target origin; snapped to the nearest surface point, which must lie "
                       "within 1% of the mesh's bounding-box diagonal.")
            .range(-1e9, 1e9)
            .paramDouble("angle", 0.0,
                         "Degrees the target's (u, v) axes turn about the origin normal, as the "
                         "source map's angle does.")
            .range(-360, 360)
            .paramDouble("scale", 1.0, "lambda: target distance = lambda x domain distance.")
            .range(1e-3, 1e3)
            .paramDouble("margin", 0.25,
                         "Coverage beyond the disk holding the source map, as a fraction of its "
                         "radius (the source cage reaches about two grid cells beyond the "
                         "canvas).")
            .range(0, 10)
            .paramBool("keep_holes", false,
                       "Keep holes of the target mesh inside the canvas (for filling them) "
                       "instead of refusing them.")
            .node<DemNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
