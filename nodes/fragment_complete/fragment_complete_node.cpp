#include <cstdint>
#include <memory>
#include <vector>

#include "fragment_complete.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

geobrush::FragmentCompleteOptions optionsOf(const Context& ctx) {
  geobrush::FragmentCompleteOptions o;
  o.levels = int(ctx.param<int>("levels"));
  o.descRes = int(ctx.param<int>("desc_res"));
  o.radius = ctx.param<double>("radius");
  o.rotations = int(ctx.param<int>("rotations"));
  o.guidanceWeight = ctx.param<double>("guidance_weight");
  o.candidateStride = int(ctx.param<int>("candidate_stride"));
  return o;
}

// The vertices the map traces to the target are original; the patch's and the seam's are not.
std::vector<std::uint8_t> originalVertices(const geobrush::PasteMap& map) {
  std::vector<std::uint8_t> original(map.targetVertex.size());
  for (std::size_t v = 0; v < original.size(); ++v)
    original[v] = map.targetVertex[v] >= 0 ? 1 : 0;
  return original;
}

class FragmentCompleteNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto map = ctx.in<geobrush::PasteMap>("paste_map");
    geobrush::FragmentCompleteResult result;
    try {
      result = geobrush::fragmentComplete(mesh->surface, originalVertices(*map), optionsOf(ctx));
    } catch (const geobrush::FragmentCompleteError& e) {
      if (e.option() == "mesh" || e.option() == "paste_map")
        throw NodeError::input(e.option(), e.what());
      throw NodeError::param(e.option(), e.what());
    }
    auto out = std::make_shared<const Mesh>(result.mesh, mesh->vertexColors);
    auto fields = std::make_shared<geobrush::VertexFields>(out->surface);
    fields->add("confidence", std::move(result.confidence));
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["completed"] = double(result.completed);
    report->values["candidates"] = double(result.candidates);
    report->values["mean_best_cost"] = result.meanBestCost;
    report->values["radius"] = result.radius;
    ctx.out("mesh", std::move(out));
    ctx.out("confidence", std::move(fields));
    ctx.out("report", std::move(report));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.fragment_complete", 1)
            .label("Fragment Complete")
            .category("Inpainting")
            .doc("Example-based completion (Freeform surface inpainting, section 6): the "
                 "vertices a smooth patch placed get fine detail copied from the original "
                 "surface, scale by scale (uniform smoothing, 4^l steps), coarsest first, rim "
                 "inward, each taking the detail of the candidate whose two-layer tangent-plane "
                 "descriptor matches best.")
            .input<Mesh>("mesh", "The closed-up mesh: the hole filled by a smooth guidance patch.")
            .input<geobrush::PasteMap>(
                "paste_map", "Which vertices came from the target (original); the rest complete.")
            .output<Mesh>("mesh", "The same connectivity, the completed vertices moved.")
            .output<geobrush::VertexFields>(
                "confidence",
                "Column 'confidence': 1 on original vertices, 0.5 exp(-rms best cost / mean "
                "edge) on completed ones.")
            .output<geobrush::Metrics>(
                "report", "Completed vertices, candidate descriptors, mean best cost, radius.")
            .paramInt("levels", 2,
                      "Detail scales; level l's base is the mesh after 4^(l+1) "
                      "uniform smoothing steps.")
            .range(1, 6)
            .paramInt("desc_res", 8, "Top-layer descriptor cells along a side (bottom: half).")
            .range(2, 64)
            .paramDouble("radius", 0, "Descriptor half-width; 0: 4 x the mean edge length.")
            .range(0, 1e9)
            .paramInt("rotations", 8, "Turns of each candidate about its normal.")
            .range(1, 360)
            .paramDouble("guidance_weight", 1,
                         "Weight of the guidance's own values in cells not yet known.")
            .range(0, 1e6)
            .paramInt("candidate_stride", 1,
                      "Every n-th original vertex is a candidate. Runs past levels x completed x "
                      "candidates x rotations x cells = 4e9 are refused: raise it.")
            .range(1, 1e9)
            .node<FragmentCompleteNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
