#include <memory>
#include <stdexcept>

#include "emd_signal.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"

namespace {

using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::VertexFields;

class EmdSignalNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    geobrush::EmdSignalOptions options;
    options.areaNormalize = ctx.param<bool>("area_normalize");
    geobrush::EmdSignal signal;
    try {
      signal = geobrush::emdSignal(mesh->surface, *geobrush::derivedMeshDifferentials(ctx, mesh),
                                   options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("mesh", e.what());
    }
    auto fields = std::make_shared<VertexFields>(mesh->surface.n_vertices(),
                                                 geobrush::derivedGeometryHash(ctx, mesh));
    fields->add("g", std::move(signal.g));
    fields->add("area", std::move(signal.area));
    ctx.out("signal", fields);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.emd_signal", 1)
            .label("EMD Signal")
            .category("EMD Transfer")
            .doc("The detail signal of EMD detail transfer (Eq. 1): g(v_i) = Delta(v_i) . n_i, "
                 "Delta the unnormalized cotangent Laplacian (sum of (cot a + cot b)(v_j - v_i)), "
                 "n_i the area-weighted unit normal. Zero on a plane, about -4 A_i / R on a "
                 "sphere of radius R (A_i the vertex area), unchanged by rigid motions. The "
                 "signal emd splits into scales.")
            .input<Mesh>("mesh", "Any triangle mesh.")
            .output<VertexFields>("signal",
                                  "Fields on the mesh: g, and area (A_i, the mixed Voronoi area "
                                  "of each vertex).")
            .paramBool("area_normalize", false,
                       "Divide g by A_i, so that it does not scale with the mesh's resolution "
                       "(a transfer between meshes of different density then keeps the "
                       "detail's height; laplacian_reconstruct's per_area undoes it).")
            .node<EmdSignalNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
