#include "canvas_grow.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

class CanvasGrowNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    geobrush::CanvasGrowOptions options;
    const auto origin = ctx.param<geobrush::Vec3>("origin");
    options.origin = {origin[0], origin[1], origin[2]};
    const auto dabs = ctx.param<std::vector<double>>("dabs");
    if (dabs.size() % 4 != 0) {
      throw NodeError::param("dabs", "needs rows of 4 numbers (x, y, z, radius)");
    }
    for (std::size_t i = 0; i + 3 < dabs.size(); i += 4)
      options.dabs.push_back({{dabs[i], dabs[i + 1], dabs[i + 2]}, dabs[i + 3]});
    try {
      ctx.out("canvas", std::make_shared<const Canvas>(geobrush::growCanvas(mesh, options)));
    } catch (const geobrush::CanvasGrowError& e) {
      if (e.option() == "mesh") throw NodeError::input("mesh", e.what());
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.canvas_grow", 1)
            .label("Grow Canvas")
            .category("Canvas")
            .doc("Grows the source canvas P_s (paper sections 3.1, 4.2): a flood fill over "
                 "edge-adjacent faces from the face under the origin through the painted faces. "
                 "A face is painted when each of its corners lies in some dab. The canvas must be "
                 "bounded by a single loop; its inside may have any genus.")
            .input<Mesh>("mesh", "The surface to paint the canvas on.")
            .output<Canvas>("canvas", "The canvas: submesh, index maps, boundary loop, origin.")
            .paramVec3("origin", {0, 0, 0},
                       "The canvas origin; snapped to the nearest surface point, which must lie "
                       "within 1% of the mesh's bounding-box diagonal.")
            .range(-1e9, 1e9)
            .paramList("dabs", 4, {},
                       "Painted dabs as rows of x, y, z, radius; the painted region is the union "
                       "of their balls.")
            .range(-1e9, 1e9)
            .node<CanvasGrowNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
