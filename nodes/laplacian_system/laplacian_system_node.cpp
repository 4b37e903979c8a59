#include <memory>
#include <stdexcept>
#include <string>

#include "geobrush/canvas.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"
#include "laplacian_system.hpp"

namespace {

using geobrush::LaplacianSystem;
using geobrush::NodeError;

class LaplacianSystemNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto target = ctx.in<geobrush::Parameterization>("target");
    const auto region = ctx.in<geobrush::Region2D>("region");
    std::vector<int> vertices;
    try {
      vertices = geobrush::targetMeshVertices(*region, *target);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("region", e.what());
    }
    if (vertices.empty())
      throw NodeError::input("region",
                             "it covers no vertex of the target: paint over the "
                             "target canvas");
    geobrush::LaplacianSystemOptions options;
    options.mu = ctx.param<double>("mu");
    options.muBoundary = ctx.param<double>("mu_boundary");
    options.outside = ctx.param<std::string>("outside") == "anchor"
                          ? geobrush::OutsideNeighbours::anchor
                          : geobrush::OutsideNeighbours::drop;
    options.form = ctx.param<std::string>("form") == "least_squares"
                       ? geobrush::LaplacianForm::leastSquares
                       : geobrush::LaplacianForm::screened;
    try {
      const auto& mesh = target->canvas->source;
      ctx.out("system", std::make_shared<const LaplacianSystem>(geobrush::buildLaplacianSystem(
                            mesh, vertices, options, geobrush::derivedGeometryHash(ctx, mesh),
                            geobrush::derivedMeshDifferentials(ctx, mesh).get())));
    } catch (const std::runtime_error& e) {
      throw NodeError::input("region", e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.laplacian_system", 1)
          .label("Laplacian System")
          .category("EMD Transfer")
          .doc("The system of EMD detail transfer Eqs. 6-8 over Q_t, the target "
               "vertices the region covers, factored (sparse LDL^T of L + M, or L^T L + M^2, L the "
               "cotangent Laplacian of Eq. 7, M = diag(mu)). It depends on the region and mu "
               "alone, so a gain change re-uses it and laplacian_reconstruct only back-"
               "substitutes; a new dab refactors.")
          .input<geobrush::Parameterization>("target",
                                             "E_t: its canvas' mesh is the one that moves.")
          .input<geobrush::Region2D>("region", "Q: its target vertices are the unknowns.")
          .output<LaplacianSystem>("system", "The factored system, for laplacian_reconstruct.")
          .paramDouble("mu", 0.1,
                       "The pull towards the original points inside the region (dimensionless: "
                       "L V and mu V are both lengths).")
          .range(1e-6, 1e6)
          .paramDouble("mu_boundary", 1.0,
                       "The pull on the region's border (its vertices with a neighbour outside), "
                       "against the boundary degeneration of an open region.")
          .range(1e-6, 1e6)
          .paramEnum("outside", "anchor", {"anchor", "drop"},
                     "anchor: every face around the region, the fixed neighbours outside moved "
                     "to the right-hand side; drop: the region solved as an open mesh of its "
                     "own faces, as the paper does: one-sided cotangents then move the border, "
                     "and a detail that would lift the whole region cannot be expressed.")
          .paramEnum("form", "screened", {"screened", "least_squares"},
                     "screened: (L + M) V^ = T + M V, the Laplacian coordinates met up to the "
                     "pull (one 1-ring factor, several times faster to factor on every dab); "
                     "least_squares: Eq. 8's normal equations (L^T L + M^2) V^ = L^T T + M^2 V "
                     "(a 2-ring factor).")
          .node<LaplacianSystemNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
