// The source side of the GPU texture cloning paper's direct projective mapping
// (../shared/papers/gpu-texture-cloning.txt, section 2, E1); the algorithm is core's
// geobrush/projective_map.hpp, shared with geobrush.dpm_target and geobrush.dpm_lift.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/node.hpp"
#include "geobrush/projective_map.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;

// Overhangs (the paper's admitted limitation): the projection folds the faces turned away from
// the view. Inside a region they are lifted with their heights all the same, but an outline that
// crosses a fold overlaps itself in the domain and cannot be stitched.
void warnAboutFolds(Context& ctx, const std::vector<std::uint8_t>& reversed) {
  const auto folded = std::count(reversed.begin(), reversed.end(), std::uint8_t(1));
  if (folded == 0) return;
  std::string message = std::to_string(folded);
  message +=
      " canvas faces are folded by the projection or lie next to a fold (turned away from "
      "the view: an overhang); a region whose outline crosses a fold cannot be pasted: turn "
      "the view or paint around it";
  ctx.warn(message);
}

class DpmNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto canvas = ctx.in<Canvas>("canvas");
    geobrush::ProjectiveMapOptions options;
    const auto view = ctx.param<geobrush::Vec3>("view");
    options.view = {view[0], view[1], view[2]};
    options.angleDegrees = ctx.param<double>("angle");
    options.centerAtVertex = ctx.param<std::string>("center") == "vertex";
    options.cropToDisc = ctx.param<bool>("crop_to_disc");
    options.reversedRing = ctx.param<int>("reversed_ring");
    try {
      geobrush::ProjectiveMapResult map = geobrush::projectiveMap(canvas, options);
      auto out = std::make_shared<Parameterization>();
      out->canvas = map.canvas;
      out->uv = std::move(map.uv);
      // Every vertex was projected along n_P.
      out->normal.assign(out->uv.size(), map.origin.normal);
      out->origin = map.origin;
      out->reversedFaces = std::move(map.reversedFaces);
      warnAboutFolds(ctx, out->reversedFaces);
      ctx.out("parameterization", std::move(out));
    } catch (const geobrush::ProjectiveMapError& e) {
      if (e.option() == "canvas") throw NodeError::input("canvas", e.what());
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.dpm", 1)
            .label("Direct Projective Map")
            .category("Parameterization")
            .doc("The source map of GPU texture cloning (gpu-texture-cloning.txt section 2, E1): "
                 "the canvas projected orthogonally onto the plane P through its centre whose "
                 "normal n_P is the view, uv = ((x - v_o) . e_u, (x - v_o) . e_v) in metric "
                 "units, axes as gdem's. Faces seen edge-on or from behind are flagged reversed.")
            .input<Canvas>("canvas", "The source canvas to parameterize.")
            .output<Parameterization>(
                "parameterization",
                "uv per canvas vertex (the cropped canvas with crop_to_disc), n_P as every "
                "vertex's normal, the plane's frame as the origin frame, the reversed flags.")
            .paramVec3("view", {0, 0, 0},
                       "The view direction n_P (any length); (0, 0, 0): the view under which the "
                       "canvas shows its largest area (its vector area), or the surface normal "
                       "at the canvas origin where the canvas nearly closes.")
            .range(-1e9, 1e9)
            .paramDouble("angle", 0.0,
                         "Degrees the v axis turns about n_P from the global +y projected onto "
                         "P (+z when n_P is along y), as gdem's angle.")
            .range(-360, 360)
            .paramEnum("center", "point", {"point", "vertex"},
                       "The centre v_o of P: the canvas origin point (uv(origin) = (0, 0), the "
                       "shared domain's convention) or the canvas origin vertex (the paper's).")
            .paramBool("crop_to_disc", false,
                       "Crop the canvas to the faces whose corners project within the largest "
                       "disc about v_o that its projected outline holds (the paper's round "
                       "decal).")
            .paramInt("reversed_ring", 3, "Vertex rings the reversed flags grow by.")
            .range(0, 100)
            .node<DpmNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
