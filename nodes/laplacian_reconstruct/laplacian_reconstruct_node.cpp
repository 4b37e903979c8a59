#include <memory>
#include <stdexcept>
#include <string>

#include "geobrush/mesh_points.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"
#include "laplacian_reconstruct.hpp"

namespace {

using geobrush::LaplacianSystem;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::VertexFields;

class LaplacianReconstructNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto system = ctx.in<LaplacianSystem>("system");
    const auto fields = ctx.in<VertexFields>("signal");
    if (fields->meshHash != system->meshHash)
      throw NodeError::input("signal", "it lies on another mesh than the system's");
    const std::string name = ctx.param<std::string>("field");
    const auto* signal = fields->find(name);
    if (!signal) throw NodeError::param("field", "input 'signal' has no field '" + name + "'");
    geobrush::ReconstructOptions options;
    options.perArea = ctx.param<bool>("per_area");
    options.keepTangential = ctx.param<std::string>("tangent") == "keep";
    geobrush::ReconstructResult result;
    try {
      result = geobrush::reconstructRegion(*system, *signal, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("signal", e.what());
    }
    // A retired result copied from the system's mesh differs from it on the region it moved
    // alone: those points are copied back, and the new region moved.
    auto recycled = ctx.recycle<Mesh, MovedBy>(
        "mesh", [&](const MovedBy& made) { return made.base == system->mesh; });
    auto moved = recycled.value;
    if (moved)
      geobrush::copyPoints(system->mesh->surface, recycled.note->vertices, moved->surface);
    else
      moved = std::make_shared<Mesh>(system->mesh->surface);
    geobrush::moveRegion(*system, result.points, moved->surface);
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["unknowns"] = double(system->vertices.size());
    report->values["border_vertices"] = double(system->boundary.size());
    report->values["max_move"] = result.maxMove;
    ctx.outRecyclable("mesh", moved,
                      std::make_shared<const MovedBy>(MovedBy{system->mesh, system->vertices}));
    ctx.out("report", report);
  }

 private:
  // What a result was copied from, held so that nothing changes it, and the vertices moved.
  struct MovedBy {
    geobrush::MeshPtr base;
    std::vector<int> vertices;
  };
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.laplacian_reconstruct", 1)
          .label("Laplacian Reconstruct")
          .category("EMD Transfer")
          .doc("The target rebuilt from the transferred signal (EMD detail transfer Eqs. 6-8): "
               "the region's points solve (L^T L + M^2) V^ = L^T T + M^2 V, T = -diag(g^) N (+ the "
               "original's tangential part), "
               "with the system laplacian_system factored; every vertex off the region keeps "
               "its bits. The sign is the erratum of Eq. 6 (as printed it inverts the detail). "
               "Normals N are the original target's, so the system is linear in g^ and the "
               "result affine in the gains.")
          .input<LaplacianSystem>("system", "laplacian_system's output for this region.")
          .input<VertexFields>("signal", "Fields on the target mesh (emd_transfer's).")
          .output<Mesh>("mesh", "The target with the region moved (same connectivity).")
          .output<geobrush::Metrics>(
              "report",
              "unknowns, border_vertices, max_move (the largest displacement); signal_fidelity "
              "measures how closely the mesh carries the signal.")
          .paramString("field", "g_hat", "The field of 'signal' to rebuild from.")
          .paramBool("per_area", false,
                     "The signal is per unit area (emd_signal's area_normalize): multiplied by "
                     "the target's vertex areas, so detail keeps its height across densities.")
          .paramEnum("tangent", "keep", {"keep", "zero"},
                     "keep: the target keeps the original's tangential Laplacian coordinates, "
                     "only their normal part is g^ (a surface rebuilt from its own signal is "
                     "itself); zero: T = -diag(g^) N alone, as the paper writes it (vertices also "
                     "slide towards a tangentially relaxed mesh).")
          .node<LaplacianReconstructNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
