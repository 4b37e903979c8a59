#include <memory>
#include <string>

#include "geobrush/border_loop.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "weld.hpp"

namespace {

using geobrush::BorderLoop;
using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

std::shared_ptr<geobrush::Metrics> report(const geobrush::WeldResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["shared_vertices"] = double(result.sharedVertices);
  v["strip_faces"] = double(result.stripFaces);
  v["border_splits"] = double(result.borderSplits);
  v["ear_splits"] = double(result.earSplits);
  v["seam_faces"] = double(result.map.seamFaces.size());
  v["patch_flipped"] = result.patchFlipped ? 1.0 : 0.0;
  v["trimmed_faces"] = double(result.trimmedFaces);
  v["snapped_vertices"] = double(result.snappedVertices);
  return metrics;
}

// The holed mesh's colours, then the patch's for its unshared vertices (its last one if none).
std::vector<geobrush::Rgb> colors(const Mesh& holed, const Mesh& patch,
                                  const geobrush::WeldResult& result) {
  std::vector<geobrush::Rgb> out = holed.vertexColors;
  if (out.empty()) return out;
  out.resize(result.mesh.n_vertices(), out.back());
  const auto& source = result.map.sourceVertex;
  for (std::size_t v = holed.surface.n_vertices(); v < out.size(); ++v)
    if (source[v] >= 0 && std::size_t(source[v]) < patch.vertexColors.size())
      out[v] = patch.vertexColors[std::size_t(source[v])];
  return out;
}

class WeldNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto border = ctx.in<BorderLoop>("border");
    const auto patch = ctx.in<Mesh>("patch");
    if (!border->mesh) throw NodeError::input("border", "the border loop has no mesh");
    geobrush::WeldOptions options;
    options.shareTolerance = ctx.param<double>("share_tolerance");
    geobrush::WeldResult result;
    try {
      result = geobrush::weld(border->mesh->surface, border->vertex, patch->surface, options);
    } catch (const geobrush::WeldError& e) {
      throw NodeError::input(e.port(), e.what());
    }
    if (result.patchFlipped)
      ctx.warn(
          "the patch faced against the holed mesh (its boundary ran along the hole's): it "
          "was turned over");
    auto out = std::make_shared<const Mesh>(result.mesh, colors(*border->mesh, *patch, result));
    ctx.out("report", report(result));
    ctx.out("paste_map", std::make_shared<const geobrush::PasteMap>(std::move(result.map)));
    ctx.out("mesh", std::move(out));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.weld", 1)
            .label("Weld")
            .category("Inpainting")
            .doc("Joins a repair patch to the holed mesh as one manifold mesh (surface "
                 "inpainting's last stage). Patch boundary vertices on border vertices become "
                 "them, in both loops' cyclic order; the gaps between consecutive shared vertices "
                 "are zipped by the shortest new edges, or the whole loops where none is shared. "
                 "Patch faces that overlap the holed mesh at the border are removed first. A "
                 "patch facing the other way is turned over, with a warning; a seam whose faces "
                 "would intersect is refused.")
            .input<BorderLoop>("border", "The hole's border loop on the holed mesh.")
            .input<Mesh>("patch", "The repair patch: one boundary loop, on or near the border.")
            .output<Mesh>("mesh",
                          "The holed mesh's vertices and faces in order, then the patch's "
                          "(shared vertices dropped), then the strip faces.")
            .output<geobrush::PasteMap>(
                "paste_map",
                "Target: the holed mesh's vertices; source: the patch's (shared ones have "
                "both); seam faces: the strips and the patch faces on shared seam edges.")
            .output<geobrush::Metrics>(
                "report",
                "shared_vertices, border_splits, ear_splits (patch edges split at an ear of "
                "the hole), trimmed_faces (patch faces that overlapped the holed mesh), "
                "snapped_vertices, strip_faces, seam_faces, patch_flipped.")
            .paramDouble("share_tolerance", 1e-6,
                         "Patch boundary vertices this close to a border vertex, relative to the "
                         "holed mesh's bounding diagonal, become that vertex.")
            .range(0.0, 0.1)
            .node<WeldNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
