#include "geobrush/canvas.hpp"
#include "geobrush/exponential_map.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;

class GdemNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto canvas = ctx.in<Canvas>("canvas");
    geobrush::DemOptions options;
    options.generalized = true;
    options.angleDegrees = ctx.param<double>("angle");
    options.neighbours = ctx.param<int>("neighbours");
    options.epsilon = ctx.param<double>("epsilon");
    options.reversedThreshold = ctx.param<double>("reversed_threshold");
    options.reversedRing = ctx.param<int>("reversed_ring");
    try {
      geobrush::DemResult dem = geobrush::discreteExponentialMap(*canvas, options);
      auto out = std::make_shared<Parameterization>();
      out->canvas = canvas;
      out->uv = std::move(dem.uv);
      out->normal = std::move(dem.normal);
      out->origin = dem.origin;
      out->reversedFaces = std::move(dem.reversedFaces);
      ctx.out("parameterization", std::move(out));
    } catch (const geobrush::DemError& e) {
      if (e.option() == "canvas") throw NodeError::input("canvas", e.what());
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.gdem", 1)
            .label("Generalized DEM")
            .category("Parameterization")
            .doc("The generalized discrete exponential map E_s of the source canvas (paper "
                 "section 4.2): Eq. 1 smoothed normals, propagation over k nearest neighbours in "
                 "order of distance from the origin, steps projected onto the tangent planes "
                 "without rescaling; plus the reversed-face flags of section 4.5.")
            .input<Canvas>("canvas", "The source canvas to parameterize.")
            .output<Parameterization>("parameterization",
                                      "uv and the Eq. 1 normal per canvas vertex, the origin frame "
                                      "and the reversed-face flags.")
            .paramDouble("angle", 0.0,
                         "Degrees the v axis turns about the origin normal from the global +y "
                         "projected onto the tangent plane (+z when the normal is along y).")
            .range(-360, 360)
            .paramInt("neighbours", 8, "k of the k-nearest-neighbour propagation graph.")
            .range(1, 64)
            .paramDouble("epsilon", 1e-3,
                         "Eq. 1's epsilon, relative to the canvas's squared bounding-box "
                         "diagonal; larger gives smoother normals.")
            .range(1e-12, 1e3)
            .paramDouble("reversed_threshold", 0.0,
                         "A face is reversed when its normal . the DEM normal is below this.")
            .range(-1, 1)
            .paramInt("reversed_ring", 3, "Vertex rings the reversed flags grow by.")
            .range(0, 100)
            .node<GdemNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
