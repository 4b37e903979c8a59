#include <memory>
#include <stdexcept>
#include <string>

#include "belt_smooth.hpp"
#include "geobrush/mesh_points.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"

namespace {

using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::VertexFields;

// A gain change rebuilds the target and smooths its belt on every edit: a retired result of this
// node (Context::recycle) with the input mesh's connectivity takes its points instead of a whole
// new copy of the mesh, and a retired paste map its entries (every one is written again).
class BeltSmoothNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto target = ctx.in<Mesh>("target");
    const auto sampled = ctx.in<VertexFields>("sampled");
    // The target's geometry hash is derived data: an edit of the gains does not hash it again.
    const geobrush::Hash targetHash = geobrush::derivedGeometryHash(ctx, target);
    if (const std::string why = sampled->mismatch(target->surface, targetHash); !why.empty())
      throw NodeError::input("sampled", why + " (input 'target')");
    if (mesh->surface.n_vertices() != target->surface.n_vertices() ||
        mesh->surface.n_faces() != target->surface.n_faces())
      throw NodeError::input("mesh", "it is not the target rebuilt (other vertex or face count)");
    const auto* region = sampled->find("region");
    const auto* nearest = sampled->find("nearest");
    if (!region || !nearest)
      throw NodeError::input("sampled", "it has no fields region and nearest (emd_correspond's)");
    std::vector<std::uint8_t> inRegion(region->size());
    for (std::size_t v = 0; v < inRegion.size(); ++v)
      inRegion[v] = (*region)[v] != 0.0;
    geobrush::BeltSmoothOptions options;
    options.rings = ctx.param<int>("rings");
    options.iterations = ctx.param<int>("iterations");
    options.lambda = ctx.param<double>("lambda");
    const auto smoothed = copyOf(ctx, *mesh);
    geobrush::BeltSmoothResult result =
        geobrush::smoothBeltInPlace(smoothed->surface, inRegion, options);
    auto map = ctx.recycle<geobrush::PasteMap, Made>("map", [](const Made&) { return true; }).value;
    if (!map) map = std::make_shared<geobrush::PasteMap>();
    map->sourceVertex.resize(nearest->size());
    map->targetVertex.resize(nearest->size());
    for (std::size_t v = 0; v < nearest->size(); ++v) {
      map->targetVertex[v] = int(v);
      map->sourceVertex[v] = int((*nearest)[v]);
    }
    map->seamFaces = std::move(result.seamFaces);
    const auto made = std::make_shared<const Made>();
    ctx.outRecyclable("mesh", smoothed, made);
    ctx.outRecyclable("map", map, made);
  }

 private:
  struct Made {};  // recycled results are checked against the input itself

  static std::shared_ptr<Mesh> copyOf(geobrush::Context& ctx, const Mesh& mesh) {
    const auto recycled = ctx.recycle<Mesh, Made>("mesh", [&](const Made&) { return true; });
    if (!recycled || !geobrush::sameConnectivity(recycled.value->surface, mesh.surface))
      return std::make_shared<Mesh>(mesh.surface);
    geobrush::copyPoints(mesh.surface, recycled.value->surface);
    return recycled.value;
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.belt_smooth", 1)
            .label("Belt Smooth")
            .category("EMD Transfer")
            .doc("The belt of EMD detail transfer (Sec. 3.5, Fig. 4d): the vertices fewer than "
                 "`rings` rings from the region's border, on both sides, moved `iterations` "
                 "times lambda of the way to their neighbours' mean (uniform weights, Jacobi), "
                 "everything else fixed, the mesh's own boundary too. Also the paste map that "
                 "metrics reads: every vertex its own target vertex, the region's its nearest "
                 "source vertex, the seam the faces across the border.")
            .input<Mesh>("mesh", "The target rebuilt (laplacian_reconstruct's).")
            .input<Mesh>("target", "The target before: what the region was painted on.")
            .input<VertexFields>("sampled", "emd_correspond's output: region and nearest.")
            .output<Mesh>("mesh", "The rebuilt target with its belt smoothed.")
            .output<geobrush::PasteMap>("map", "For metrics and compare.")
            .paramInt("rings", 2, "The belt's width in rings on each side of the border.")
            .range(1, 16)
            .paramInt("iterations", 3, "Smoothing passes; 0 leaves the mesh as it is.")
            .range(0, 1000)
            .paramDouble("lambda", 0.5, "The share of the way to the neighbours' mean per pass.")
            .range(1e-6, 1.0)
            .node<BeltSmoothNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
