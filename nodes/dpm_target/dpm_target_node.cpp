#include <memory>
#include <numbers>

#include "dpm_target.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;

// Dragging the stamp re-evaluates this node on the same target mesh: its StampTarget
// (nearest-point search) is derived data the framework keeps.
class DpmTargetNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto source = ctx.in<Parameterization>("source");
    geobrush::ProjectiveStampOptions options;
    const auto origin = ctx.param<geobrush::Vec3>("origin");
    const auto view = ctx.param<geobrush::Vec3>("view");
    options.origin = {origin[0], origin[1], origin[2]};
    options.view = {view[0], view[1], view[2]};
    options.angleDegrees = ctx.param<double>("angle");
    options.scale = ctx.param<double>("scale");
    options.margin = ctx.param<double>("margin");
    options.keepHoles = ctx.param<bool>("keep_holes");
    try {
      const auto target = ctx.derived("dpm_stamp_target", {"mesh"}, 0, [&] {
        return std::make_shared<const geobrush::StampTarget>(mesh);
      });
      geobrush::ProjectiveStampResult stamp =
          geobrush::projectiveStamp(*target, source->uv, options);
      auto out = std::make_shared<Parameterization>();
      out->canvas = std::make_shared<const geobrush::Canvas>(std::move(stamp.canvas));
      out->uv = std::move(stamp.uv);
      out->normal.assign(out->uv.size(), stamp.origin.normal);
      out->origin = stamp.origin;
      out->rotation = options.angleDegrees * std::numbers::pi / 180;
      out->scale = options.scale;
      out->reversedFaces = std::move(stamp.reversedFaces);
      ctx.out("parameterization", std::move(out));
    } catch (const geobrush::ProjectiveStampError& e) {
      if (e.option() == "mesh" || e.option() == "source")
        throw NodeError::input(e.option(), e.what());
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.dpm_target", 1)
            .label("Target Projective Stamp")
            .category("Parameterization")
            .doc("The target stamp of GPU texture cloning: the direct projective map around the "
                 "target origin, uv = R_angle ((x - o) . e_u, (x - o) . e_v) / scale, on the "
                 "faces connected to the origin whose projection meets the disc holding the "
                 "source map plus the margin. Ports and params as geobrush.dem's.")
            .input<Mesh>("mesh", "The target surface.")
            .input<Parameterization>("source", "The source map: the domain region to cover.")
            .optionalInput<geobrush::Cage>(
                "source_cage",
                "Accepted for graphs made for geobrush.dem and ignored: the stamp covers the "
                "source map's disc plus the margin.")
            .output<Parameterization>("parameterization",
                                      "The target canvas with uv in the shared domain, n_PT as "
                                      "every vertex's normal, the plane's frame, rotation, "
                                      "scale and the reversed (folded) faces.")
            .paramVec3("origin", {0, 0, 0},
                       "The target origin; snapped to the nearest surface point, which must lie "
                       "within 1% of the mesh's bounding-box diagonal.")
            .range(-1e9, 1e9)
            .paramVec3("view", {0, 0, 0},
                       "The view direction n_PT (any length); (0, 0, 0): the surface normal at "
                       "the snapped origin.")
            .range(-1e9, 1e9)
            .paramDouble("angle", 0.0,
                         "Degrees the target's (u, v) axes turn about n_PT, as the source map's "
                         "angle does.")
            .range(-360, 360)
            .paramDouble("scale", 1.0, "lambda: target distance = lambda x domain distance.")
            .range(1e-3, 1e3)
            .paramDouble("margin", 0.25,
                         "Coverage beyond the disc holding the source map, as a fraction of its "
                         "radius.")
            .range(0, 10)
            .paramBool("keep_holes", false,
                       "Keep holes of the target mesh inside the stamp, and let it run onto the "
                       "mesh's boundary, instead of refusing both.")
            .node<DpmTargetNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
