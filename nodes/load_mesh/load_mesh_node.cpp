#include "geobrush/mesh.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "load_mesh.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

class LoadMeshNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    geobrush::LoadMeshOptions options;
    options.repair = ctx.param<bool>("repair");
    options.progress = [&ctx](double fraction) {
      ctx.throwIfCancelled();
      ctx.progress(fraction);
    };
    geobrush::LoadMeshResult loaded;
    try {
      loaded = geobrush::loadMesh(ctx.path("path"), options);
    } catch (const geobrush::MeshError& e) {
      throw NodeError::param("path", e.what());
    }
    for (const auto& warning : loaded.warnings)
      ctx.warn(warning);
    ctx.out("mesh", loaded.mesh);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.load_mesh", 1)
            .label("Load mesh")
            .category("IO")
            .doc("Reads a triangle mesh from an OBJ, PLY, OFF or STL file. Polygons are "
                 "triangulated and unusable faces dropped, each with a warning; a file with no "
                 "usable faces, a non-finite coordinate or (unless repaired) non-manifold faces "
                 "is an error. OBJ keeps full double precision; PLY, OFF and STL hold 32-bit "
                 "floats.")
            .output<Mesh>("mesh", "The mesh, with the file's vertex order.")
            .paramInputPath("path", "The mesh file, relative to the graph file's folder.")
            .paramBool("repair", false,
                       "Split faces that make an edge or vertex non-manifold (or flip the "
                       "orientation) off onto their own vertices, with a warning, instead of "
                       "failing.")
            .node<LoadMeshNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
