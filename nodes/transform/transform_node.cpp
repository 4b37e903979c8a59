#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "transform.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

Eigen::Vector3d vec3Param(const Context& ctx, std::string_view name) {
  const auto v = ctx.param<geobrush::Vec3>(name);
  return {v[0], v[1], v[2]};
}

class TransformNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto input = ctx.in<Mesh>("mesh");
    geobrush::TransformOptions options;
    options.translate = vec3Param(ctx, "translate");
    options.rotateDegrees = vec3Param(ctx, "rotate");
    options.scale = vec3Param(ctx, "scale");
    options.pivot = vec3Param(ctx, "pivot");
    try {
      ctx.out("mesh", std::make_shared<const Mesh>(geobrush::transformMesh(input->surface, options),
                                                   input->vertexColors));
    } catch (const geobrush::TransformOptionError& e) {
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.transform", 1)
            .label("Transform")
            .category("Mesh")
            .doc("Scales, rotates and moves a mesh: p' = translate + pivot + R * S * (p - pivot). "
                 "Mirroring keeps faces outward-oriented.")
            .input<Mesh>("mesh", "The mesh to transform.")
            .output<Mesh>("mesh", "The transformed mesh, with the same vertex order and colours.")
            .paramVec3("translate", {0, 0, 0}, "Offset added after rotation and scale.")
            .range(-1e9, 1e9)
            .paramVec3("rotate", {0, 0, 0},
                       "Rotation in degrees about the x, then y, then z axis (through the pivot).")
            .range(-360, 360)
            .paramVec3("scale", {1, 1, 1},
                       "Scale along x, y and z about the pivot, applied before rotation; no entry "
                       "may be 0, negative entries mirror.")
            .range(-1e9, 1e9)
            .paramVec3("pivot", {0, 0, 0}, "The point that rotation and scale keep fixed.")
            .range(-1e9, 1e9)
            .node<TransformNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
