// geobrush.cage_mesh: a cage as a plain mesh, to render, save or measure it.
#include "geobrush/canvas.hpp"
#include "geobrush/registry.hpp"

namespace geobrush {
namespace {

void cageMesh(Context& ctx) {
  auto cage = ctx.in<Cage>("cage");
  if (cage->mesh.n_faces() == 0) throw NodeError::input("cage", "the cage has no faces");
  ctx.out("mesh", std::make_shared<const Mesh>(cage->mesh));
}

void registerNodes(PluginRegistrar& registrar) {
  registrar.add(NodeTypeBuilder("geobrush.cage_mesh", 1)
                    .label("Cage mesh")
                    .category("Display")
                    .doc("Outputs a cage's closed triangle mesh, to render or save it.")
                    .input<Cage>("cage", "A source or target cage.")
                    .output<Mesh>("mesh", "The cage as a mesh.")
                    .compute(cageMesh)
                    .build());
}

}  // namespace
}  // namespace geobrush

GEOBRUSH_PLUGIN(geobrush::registerNodes)
