// geobrush.cage_build: the shell cage C_s around the source canvas.
#include "cage_build.hpp"
#include "geobrush/registry.hpp"

namespace geobrush {
namespace {

void buildCageNode(Context& ctx) {
  auto param = ctx.in<Parameterization>("parameterization");
  CageBuildOptions options;
  options.resolution = ctx.param<int>("resolution");
  options.margin = ctx.param<double>("margin");
  options.constraintWeight = ctx.param<double>("constraint_weight");
  options.cancelled = [&ctx] { return ctx.cancelled(); };
  try {
    CageBuildResult result = buildCage(*param, options);
    if (result.attempts > 1)
      ctx.warn("the cage took " + std::to_string(result.attempts) +
               " attempts: smoothing uncovered canvas vertices or folded the shell");
    ctx.out("cage", std::make_shared<const Cage>(std::move(result.cage)));
  } catch (const CageBuildError& e) {
    ctx.throwIfCancelled();
    throw NodeError::input("parameterization", e.what());
  }
}

void registerNodes(PluginRegistrar& registrar) {
  registrar.add(
      NodeTypeBuilder("geobrush.cage_build", 1)
          .label("Cage build")
          .category("Preprocess")
          .doc("Builds a closed shell cage around a parameterized canvas: a coarse grid "
               "triangulation of the parameter domain, doubled into top and bottom sheets, placed "
               "by extremal projections along the normals and smoothed (GeoBrush section 4.3).")
          .input<Parameterization>("parameterization", "The canvas and its (generalized) DEM.")
          .output<Cage>("cage", "The closed, outward-oriented cage enclosing every canvas vertex.")
          .paramInt("resolution", 8, "Cells of the domain grid across its larger side.")
          .range(2, 200)
          .paramDouble("margin", 0.05,
                       "Extra thickness on both sides, as a fraction of the domain's size.")
          .range(0.0, 1.0)
          .paramDouble("constraint_weight", 1.0,
                       "Weight of the extremal positions against smoothness.")
          .range(1e-3, 1e3)
          .compute(buildCageNode)
          .build());
}

}  // namespace
}  // namespace geobrush

GEOBRUSH_PLUGIN(geobrush::registerNodes)
