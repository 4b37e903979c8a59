#include <memory>
#include <stdexcept>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "metrics.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::PasteMap;

// The new vertices against the reference surface (a hole case's removed patch).
void measureReference(const Context& ctx, const geobrush::TriMesh& result, const PasteMap* map,
                      geobrush::PasteMetrics& measured) {
  const auto reference = ctx.in<Mesh>("reference");
  if (reference->surface.n_faces() == 0) throw NodeError::input("reference", "it has no face");
  if (!map) throw NodeError::input("map", "measuring against a reference needs the paste's map");
  geobrush::measureAgainstReference(result, *map, reference->surface, measured);
}

class MetricsNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto map = ctx.hasInput("map") ? ctx.in<PasteMap>("map") : nullptr;
    const auto target = ctx.hasInput("target") ? ctx.in<Mesh>("target") : nullptr;
    const auto source = ctx.hasInput("source") ? ctx.in<Parameterization>("source") : nullptr;
    if (source && !source->canvas) throw NodeError::input("source", "the map has no canvas");
    geobrush::PasteMetricsOptions options;
    options.seamBand = ctx.param<int>("seam_band");
    geobrush::PasteMetrics measured;
    try {
      measured =
          geobrush::measurePaste(mesh->surface, map.get(), target ? &target->surface : nullptr,
                                 source ? &source->canvas->surface : nullptr, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("map", e.what());
    }
    if (ctx.hasInput("reference")) measureReference(ctx, mesh->surface, map.get(), measured);
    const auto invalid = geobrush::invalidPaste(measured);
    auto metrics = std::make_shared<geobrush::Metrics>();
    metrics->values = std::move(measured.values);
    metrics->notes = std::move(measured.notes);
    for (const auto& note : metrics->notes)
      ctx.warn(note);
    if (invalid && ctx.param<bool>("require_valid"))
      throw NodeError::input(
          "mesh", *invalid + ": nothing is written (require_valid=false writes it all the same)");
    ctx.out("metrics", std::move(metrics));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.metrics", 1)
            .label("Paste Metrics")
            .category("Analysis")
            .doc("Measures a paste on its result mesh. Seam C0: manifold, non_manifold_vertices, "
                 "components, boundary_loops (and target_boundary_loops), "
                 "seam_unshared_vertices. Seam C1: seam_normal_jump_mean_deg and _p95_deg across "
                 "the seam strips' edges, next to target_dihedral_mean_deg and _p95_deg, the "
                 "target's own angles around the seam vertices. Detail: "
                 "detail_difference_percent, the difference of Laplacian-coordinate magnitudes "
                 "between the pasted vertices away from the seam and the source canvas', after "
                 "scaling by scale_ratio. new_self_intersections: intersecting face pairs with a "
                 "pasted or seam face. With a reference (a hole's removed patch): "
                 "reference_mean_distance and reference_max_distance of the new vertices over "
                 "the bounding-box diagonal, reference_normal_mean_deg; and the other way, "
                 "reference_to_result_mean_distance and reference_to_result_max_distance of "
                 "the reference's vertices to the result.")
            .input<Mesh>("mesh", "The result of a paste.")
            .optionalInput<PasteMap>("map",
                                     "Where each vertex came from and the seam faces (the "
                                     "paste node's map); without it only the C0 checks run.")
            .optionalInput<Mesh>("target",
                                 "The mesh pasted into, for its boundary loops and "
                                 "dihedral angles.")
            .optionalInput<Parameterization>("source",
                                             "The source map, whose canvas the detail is "
                                             "compared with.")
            .optionalInput<Mesh>("reference",
                                 "The surface a fill should follow, e.g. the patch a hole case "
                                 "removed; needs the map.")
            .output<geobrush::Metrics>("metrics", "The measurements and notes.")
            .paramInt("seam_band", 3,
                      "Pasted vertices this many edges from the seam or closer are left out of "
                      "the detail measure.")
            .range(0, 100)
            .paramBool("require_valid", false,
                       "Fail, so that the evaluation writes nothing, when the paste is not "
                       "manifold, leaves more boundary loops than the target or has new "
                       "self-intersections.")
            .node<MetricsNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
