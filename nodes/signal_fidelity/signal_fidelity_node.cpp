#include <memory>
#include <stdexcept>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"
#include "signal_fidelity.hpp"

namespace {

using geobrush::LaplacianSystem;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::VertexFields;

// A measurement apart from laplacian_reconstruct, so that an edit evaluated for its mesh alone
// (a gain moved in the studio) does not pay for it.
class SignalFidelityNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto system = ctx.in<LaplacianSystem>("system");
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto fields = ctx.in<VertexFields>("signal");
    if (fields->meshHash != system->meshHash)
      throw NodeError::input("signal", "it lies on another mesh than the system's");
    if (mesh->surface.n_vertices() != system->mesh->surface.n_vertices() ||
        mesh->surface.n_faces() != system->mesh->surface.n_faces())
      throw NodeError::input("mesh",
                             "it is not the system's mesh rebuilt (other vertex or "
                             "face count)");
    const std::string name = ctx.param<std::string>("field");
    const auto* signal = fields->find(name);
    if (!signal) throw NodeError::param("field", "input 'signal' has no field '" + name + "'");
    auto report = std::make_shared<geobrush::Metrics>();
    report->values["signal_fidelity"] = geobrush::signalFidelity(
        *system, mesh->surface, *signal, {.perArea = ctx.param<bool>("per_area")});
    ctx.out("report", report);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.signal_fidelity", 1)
            .label("Signal Fidelity")
            .category("EMD Transfer")
            .doc("How closely a rebuilt surface carries the signal it was rebuilt from: "
                 "|g(mesh) - g^| / |g^| over the region of the system off its border, g(mesh) "
                 "Eq. 1's signal measured on the mesh. 0 for a surface that carries g^ exactly.")
            .input<LaplacianSystem>("system", "laplacian_system's output: the region measured.")
            .input<Mesh>("mesh", "The surface rebuilt (laplacian_reconstruct's mesh).")
            .input<VertexFields>("signal", "The fields it was rebuilt from (emd_transfer's).")
            .output<geobrush::Metrics>("report", "signal_fidelity.")
            .paramString("field", "g_hat", "The field of 'signal' the mesh was rebuilt from.")
            .paramBool("per_area", false,
                       "The signal is per unit area (laplacian_reconstruct's per_area): the "
                       "measured signal is divided by the vertex areas.")
            .node<SignalFidelityNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
