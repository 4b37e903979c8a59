// geobrush.cage_fit: the target cage C_t, fitted to the target canvas.
#include "cage_fit.hpp"
#include "geobrush/registry.hpp"

namespace geobrush {
namespace {

// The factorization and the source columns are derived data the framework keeps: dragging the
// target canvas changes only the right-hand side.
class CageFitNode final : public Node {
 public:
  void compute(Context& ctx) override {
    auto cage = ctx.in<Cage>("source_cage");
    auto source = ctx.in<Parameterization>("source");
    auto target = ctx.in<Parameterization>("target");
    CageFitOptions options;
    options.constraintWeight = ctx.param<double>("constraint_weight");
    try {
      const Hash weight = Hasher().f64(options.constraintWeight).digest();
      const auto solver = ctx.derived("cage_fit_solver", {"source_cage"}, weight, [&] {
        return std::make_shared<CageFitSolver>(*cage, options.constraintWeight);
      });
      const auto columns = ctx.derived("cage_fit_columns", {"source_cage", "source"}, 0, [&] {
        return std::make_shared<SourceColumns>(*cage, *source);
      });
      CageFitResult result = fitCage(*cage, *source, *target, options, solver.get(), columns.get());
      if (result.columnsOutsideTarget > 0)
        ctx.warn(std::to_string(result.columnsOutsideTarget) +
                 " cage columns lie outside the target canvas' parameter domain; grow the target "
                 "canvas further");
      ctx.out("target_cage", std::make_shared<const Cage>(std::move(result.cage)));
    } catch (const CageFitError& e) {
      throw NodeError::input("source_cage", e.what());
    }
  }
};

void registerNodes(PluginRegistrar& registrar) {
  registrar.add(
      NodeTypeBuilder("geobrush.cage_fit", 1)
          .label("Cage fit")
          .category("Preprocess")
          .doc("Fits the source cage to the target canvas by Laplacian editing: each cage "
               "Laplacian turned by the change of local frame and scaled by lambda, boundary "
               "midpoints placed over the target (GeoBrush Eq. 2).")
          .input<Cage>("source_cage", "The cage built around the source canvas.")
          .input<Parameterization>("source", "The source canvas' parameterization.")
          .input<Parameterization>("target", "The target canvas' parameterization.")
          .output<Cage>("target_cage", "The cage with the same connectivity over the target.")
          .paramDouble("constraint_weight", 10.0,
                       "Weight of the boundary-midpoint constraints against the Laplacians.")
          .range(1e-3, 1e6)
          .node<CageFitNode>()
          .build());
}

}  // namespace
}  // namespace geobrush

GEOBRUSH_PLUGIN(geobrush::registerNodes)
