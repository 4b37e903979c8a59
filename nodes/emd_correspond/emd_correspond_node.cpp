#include <memory>
#include <stdexcept>
#include <string>

#include "emd_correspond.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"

namespace {

using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Region2D;
using geobrush::VertexFields;

// A dab re-samples the region on fields of the whole target: a retired output of this node
// (Context::recycle) with the same fields on the same mesh has the region it was written on
// cleared (0, and -1 for nearest) instead of a new set of fields of the target's size.
class EmdCorrespondNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto region = ctx.in<Region2D>("region");
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    const auto modes = ctx.in<VertexFields>("source_modes");
    const auto& sourceMesh = source->canvas->source;
    if (const std::string why =
            modes->mismatch(sourceMesh->surface, geobrush::derivedGeometryHash(ctx, sourceMesh));
        !why.empty())
      throw NodeError::input("source_modes", why + " (the mesh of input 'source')");
    const std::vector<std::string> names = modes->modeNames();
    if (names.empty())
      throw NodeError::input("source_modes", "it has no intrinsic modes (fields h1, h2, ...)");
    std::vector<const std::vector<double>*> columns;
    for (const auto& name : names)
      columns.push_back(&modes->column(name));
    geobrush::EmdCorrespondOptions options;
    options.neighbours = ctx.param<int>("neighbours");
    if (ctx.param<std::string>("signal") == "per_area") options.factor = 1.0 / target->scale;
    if (source->uv.empty()) throw NodeError::input("source", "its canvas has no vertices");
    geobrush::RegionCorrespondence result;
    try {
      result =
          geobrush::correspondRegion(*source, *geobrush::derivedDomainNeighbours(ctx, "source"),
                                     *target, region->targetVertices, columns, options);
    } catch (const std::out_of_range& e) {
      throw NodeError::param("neighbours", e.what());
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("region", e.what());
    }
    std::vector<std::string> fieldNames = names;
    fieldNames.insert(fieldNames.end(), {"region", "nearest"});
    const auto& targetMesh = target->canvas->source;
    auto sampled = fieldsOn(ctx, targetMesh->surface.n_vertices(),
                            geobrush::derivedGeometryHash(ctx, targetMesh), fieldNames);
    const std::size_t modeCount = names.size();
    for (std::size_t i = 0; i < result.meshVertices.size(); ++i) {
      const std::size_t v = std::size_t(result.meshVertices[i]);
      for (std::size_t k = 0; k < modeCount; ++k)
        sampled->columns[k].second[v] = result.sampled[k][i];
      sampled->columns[modeCount].second[v] = 1.0;
      sampled->columns[modeCount + 1].second[v] = result.nearest[i];
    }
    auto written =
        std::make_shared<Written>(Written{sampled->meshHash, sampled->vertexCount,
                                          std::move(fieldNames), std::move(result.meshVertices)});
    ctx.outRecyclable("sampled", sampled, std::shared_ptr<const Written>(std::move(written)));
  }

 private:
  // What a published output holds beside its default values: its fields and the vertices written.
  struct Written {
    geobrush::Hash meshHash = 0;
    std::size_t vertexCount = 0;
    std::vector<std::string> names;
    std::vector<int> vertices;
  };

  // Fields named `names` on the mesh, every value 0 but the last field's (-1): a recycled output
  // cleared where it was written, or new ones.
  static std::shared_ptr<VertexFields> fieldsOn(geobrush::Context& ctx, std::size_t vertexCount,
                                                geobrush::Hash meshHash,
                                                const std::vector<std::string>& names) {
    const auto recycled = ctx.recycle<VertexFields, Written>("sampled", [&](const Written& made) {
      return made.meshHash == meshHash && made.vertexCount == vertexCount && made.names == names;
    });
    const std::size_t nearest = names.size() - 1;
    if (recycled) {
      for (int v : recycled.note->vertices)
        for (std::size_t k = 0; k < names.size(); ++k)
          recycled.value->columns[k].second[std::size_t(v)] = k == nearest ? -1.0 : 0.0;
      return recycled.value;
    }
    auto fields = std::make_shared<VertexFields>(vertexCount, meshHash);
    for (std::size_t k = 0; k < names.size(); ++k)
      fields->add(names[k], std::vector<double>(vertexCount, k == nearest ? -1.0 : 0.0));
    return fields;
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.emd_correspond", 1)
            .label("EMD Correspond")
            .category("EMD Transfer")
            .doc("The correspondence of EMD detail transfer (Sec. 3.3) and the source half of "
                 "Eq. 4: each target vertex in Q_t takes the k source canvas vertices nearest to "
                 "it in the shared (u, v) domain (a kd-tree) and the mean of each source mode "
                 "over them, H_k^s. A node of its own so that the gains of emd_transfer change "
                 "without searching again.")
            .input<Region2D>("region", "Q: its target vertices are the ones that receive detail.")
            .input<Parameterization>("source", "E_s, the source canvas' parameterization.")
            .input<Parameterization>("target", "E_t, the target canvas' parameterization.")
            .input<VertexFields>("source_modes",
                                 "emd's output on the source mesh: h1..hm transfer, r does not.")
            .output<VertexFields>(
                "sampled",
                "Fields on the target mesh: h1..hm (H_k^s on Q_t, 0 elsewhere), region (1 on "
                "Q_t), nearest (the source canvas vertex nearest in the domain, -1 off Q_t).")
            .paramInt("neighbours", 4, "k: source vertices averaged per target vertex.")
            .range(1, 64)
            .paramEnum("signal", "raw", {"raw", "per_area"},
                       "raw: the modes as they are (the paper's; right for meshes of one "
                       "density pasted at scale 1); per_area: modes of a signal per unit area "
                       "(emd_signal's area_normalize), divided by the paste's scale lambda, so "
                       "that the detail keeps its shape when the paste scales it.")
            .node<EmdCorrespondNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
