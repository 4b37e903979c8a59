#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "primitive.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

class PrimitiveNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    geobrush::PrimitiveOptions options;
    options.size = ctx.param<double>("size");
    options.minorRadius = ctx.param<double>("minor_radius");
    options.height = ctx.param<double>("height");
    options.resolution = ctx.param<int>("resolution");
    options.relief = ctx.param<double>("relief");
    options.reliefFrequency = ctx.param<double>("relief_frequency");
    options.progress = [&ctx](double fraction) {
      ctx.throwIfCancelled();
      ctx.progress(fraction);
    };
    try {
      options.shape = geobrush::parsePrimitiveShape(ctx.param<std::string>("shape"));
      ctx.out("mesh", std::make_shared<const Mesh>(geobrush::makePrimitive(options)));
    } catch (const geobrush::PrimitiveOptionError& e) {
      throw NodeError::param(e.option(), e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.primitive", 1)
            .label("Primitive")
            .category("Mesh")
            .doc("Generates a plane, sphere, rounded cube, torus or open cylinder mesh, "
                 "optionally with procedural relief, so graphs run without input files and "
                 "templates have exact shapes.")
            .output<Mesh>("mesh",
                          "The generated triangle mesh: closed and outward-facing, except the "
                          "plane, an open square facing +z, and the cylinder, an open tube.")
            .paramEnum("shape", "sphere", geobrush::primitiveShapeNames(),
                       "Which surface: plane (square at z = 0), sphere (geodesic), rounded_cube, "
                       "torus or cylinder (an open tube; both around the z axis).")
            .paramDouble("size", 1.0,
                         "Plane side length, sphere radius, cube half-extent, torus major "
                         "radius or cylinder radius.")
            .range(1e-6, 1e6)
            .paramDouble("minor_radius", 0.25,
                         "Torus tube radius (below size) or rounded-cube edge radius (at most "
                         "size); unused by the plane and sphere.")
            .range(1e-6, 1e6)
            .paramDouble("height", 2.0, "Cylinder height along z; unused by the other shapes.")
            .range(1e-6, 1e6)
            .paramInt("resolution", 64,
                      "Plane: quads per side; sphere: segments per icosahedron edge; rounded "
                      "cube: quads per face side; torus: segments around the major circle; "
                      "cylinder: segments around.")
            .range(1, 1000)
            .paramDouble("relief", 0.0,
                         "Amplitude of the procedural relief along the normal; 0 gives the exact "
                         "shape.")
            .range(0, 1e6)
            .paramDouble("relief_frequency", 4.0, "Relief noise cells per size length.")
            .range(1e-3, 1e3)
            .node<PrimitiveNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
