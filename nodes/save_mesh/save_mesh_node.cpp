#include "geobrush/mesh.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "save_mesh.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

class SaveMeshNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto destination = ctx.path("path");
    geobrush::SaveMeshPlan plan;
    try {
      plan = geobrush::planMeshSave(*mesh, {destination});
    } catch (const geobrush::MeshError& e) {
      throw NodeError::param("path", e.what());
    }
    // The evaluator renames the temporary file onto the destination only when the whole graph
    // succeeds, so the format comes from the plan, not from the temporary file's name.
    ctx.writeFile(destination, [&](const std::filesystem::path& tmp) {
      try {
        geobrush::writeMesh(*mesh, tmp, plan.format);
      } catch (const geobrush::MeshError& e) {
        throw NodeError::param("path", "cannot write '" + destination.string() + "': " + e.what());
      }
    });
    for (const auto& warning : plan.warnings)
      ctx.warn(warning);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.save_mesh", 1)
            .label("Save mesh")
            .category("IO")
            .doc("Writes a mesh to an OBJ, PLY, OFF or STL file, chosen by the extension. The "
                 "file appears only when the whole graph evaluation succeeds. OBJ keeps every "
                 "coordinate exact; what another format cannot hold (32-bit precision, colours, "
                 "STL's unshared corners) is reported as a warning. It has no outputs: nodes "
                 "that need the mesh connect to where it comes from, so that they do not wait "
                 "for, or fail with, the write.")
            .input<Mesh>("mesh", "The mesh to save.")
            .paramOutputPath("path", "result.obj",
                             "The file to write, relative to the output folder; its folder must "
                             "exist.")
            .node<SaveMeshNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
