#include <cmath>
#include <memory>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "variational_paste.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Region2D;

std::shared_ptr<geobrush::Metrics> reportValue(const geobrush::VariationalPasteReport& report) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  metrics->values = {{"unknown_vertices", double(report.unknownVertices)},
                     {"ring_vertices", double(report.ringVertices)},
                     {"rotations", double(report.rotations)},
                     {"linear_iterations", report.linearIterations},
                     {"rotation_iterations", report.rotationIterations},
                     {"initial_energy", report.initialEnergy},
                     {"final_energy", report.finalEnergy}};
  if (!report.solver.empty()) metrics->notes.push_back(report.solver);
  return metrics;
}

void checkDraft(const geobrush::TriMesh& draft, const Parameterization& source) {
  const geobrush::TriMesh& canvas = source.canvas->surface;
  if (draft.n_vertices() != canvas.n_vertices() || draft.n_faces() != canvas.n_faces())
    throw NodeError::input("draft",
                           "the draft does not have the source canvas' vertices and faces");
  for (auto v : draft.vertices())
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(draft.point(v)[k]))
        throw NodeError::input("draft", "vertex " + std::to_string(v.idx()) + " is not finite");
}

// The target's stitch base is derived data, shared with a geobrush.stitch on the same target.
class VariationalPasteNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto region = ctx.in<Region2D>("region");
    const auto source = ctx.in<Parameterization>("source");
    const auto draft = geobrush::draftOrZero(ctx);
    const auto target = ctx.in<Parameterization>("target");
    checkDraft(draft->surface, *source);
    if (region->empty()) ctx.warn("the region is empty: the target is unchanged");

    geobrush::VariationalPasteOptions options;
    options.rotationInvariant = ctx.param<bool>("rotation_invariant");
    options.rotationWeight = ctx.param<double>("rotation_weight");
    options.maxIterations = ctx.param<int>("max_iterations");
    options.tolerance = ctx.param<double>("tolerance");
    options.cancelled = [&ctx] { return ctx.cancelled(); };
    options.progress = [&ctx](double fraction) { ctx.progress(fraction); };
    geobrush::VariationalPasteResult result;
    try {
      const auto base = geobrush::derivedStitchBase(ctx, "target");
      result = geobrush::variationalPaste(*region, *source, draft->surface, *target, options,
                                          base.get());
    } catch (const geobrush::StitchError& e) {
      throw NodeError::input("target", e.what());
    } catch (const geobrush::VariationalPasteError& e) {
      throw NodeError::input("region", e.what());
    } catch (const geobrush::VariationalPasteSolveError& e) {
      if (e.cancelled()) ctx.throwIfCancelled();
      // Nothing is output: a half-solved paste is no paste.
      throw NodeError::param("max_iterations", e.what());
    }
    ctx.out("mesh", std::make_shared<const Mesh>(std::move(result.mesh)));
    ctx.out("map", std::make_shared<const geobrush::PasteMap>(std::move(result.map)));
    ctx.out("report", reportValue(result.report));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.variational_paste", 1)
            .label("Variational Paste")
            .category("Real-time")
            .doc("Pastes R_in into the target by solving the paper's Eq. 3 (section 4.4) on the "
                 "irregular stitched mesh with Ceres: min sum |L x - delta|^2, L the mean-value "
                 "Laplacian in the parameter domain, delta the draft's Laplacian coordinates, and "
                 "two rings of target vertices fixed around the seam (position and slope). The "
                 "exact, slow reference for membrane + stitch, wired the same way and giving the "
                 "same mesh topology. Optionally rotation-invariant: a local rotation per vertex, "
                 "fitted to its one-ring, turns its Laplacian coordinate (non-linear, "
                 "Levenberg-Marquardt). A solve that does not converge is an error and outputs "
                 "nothing.")
            .input<Region2D>("region", "Q with R_in and the covered target vertices.")
            .input<Parameterization>("source", "E_s: the source canvas and its map.")
            .optionalInput<Mesh>("draft",
                                 "G(P_s): the source canvas warped by the cages. Unconnected, "
                                 "G = 0: the paste is a smooth fill (hole filling).")
            .input<Parameterization>("target", "E_t: the target canvas, on the target mesh.")
            .output<Mesh>("mesh", "The target mesh with the paste solved and stitched in.")
            .output<geobrush::PasteMap>("map",
                                        "Where each result vertex came from and the seam faces, "
                                        "as geobrush.stitch gives them: the input of "
                                        "geobrush.metrics.")
            .output<geobrush::Metrics>("report",
                                       "The solve: unknown and ring vertices, rotations, Ceres "
                                       "iterations, the energy before and after, Ceres' brief "
                                       "report.")
            .paramBool("rotation_invariant", false,
                       "Off: the linear Eq. 3. On: each vertex's Laplacian coordinate may turn "
                       "with a local rotation, so that a draft turned against the target keeps "
                       "its detail's shape (non-linear, slower).")
            .paramDouble("rotation_weight", 1.0,
                         "Rotation-invariant only: weight of the term tying each vertex's rotation "
                         "to how its one-ring turned from the draft, relative to the Laplacian "
                         "term. Larger: stiffer, as-rigid-as-possible.")
            .range(1e-3, 1e3)
            .paramInt("max_iterations", 100, "Levenberg-Marquardt iterations at most, per solve.")
            .range(1, 10000)
            .paramDouble("tolerance", 1e-10,
                         "Converged when an iteration lowers the energy by less than this "
                         "fraction of it.")
            .range(1e-16, 1e-2)
            .node<VariationalPasteNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
