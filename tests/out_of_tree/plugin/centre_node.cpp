#include "centre.hpp"
#include "geobrush/registry.hpp"

namespace {

using namespace geobrush;

void centre(Context& ctx) {
  auto in = ctx.in<Mesh>("mesh");
  try {
    auto result = example::centreMesh(in->surface);
    ctx.out("mesh", std::make_shared<const Mesh>(std::move(result.mesh), in->vertexColors));
  } catch (const std::invalid_argument& e) {
    throw NodeError::input("mesh", e.what());
  }
}

void registerNodes(PluginRegistrar& registrar) {
  registrar.add(NodeTypeBuilder("example.centre", 1)
                    .label("Centre")
                    .category("Example")
                    .doc("Moves a mesh so that its area-weighted centroid is at the origin.")
                    .input<Mesh>("mesh", "The mesh to move.")
                    .output<Mesh>("mesh", "The centred mesh.")
                    .compute(centre)
                    .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
