// geobrush.render: draws a mesh (and an optional overlay mesh) into an image
// and a PNG file, with core's offscreen renderer.
#include <optional>

#include "geobrush/field_colors.hpp"
#include "geobrush/image.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/render.hpp"
#include "geobrush/vertex_fields.hpp"

namespace geobrush {
namespace {

Rgb toRgb(const Vec3& color) {
  return {float(color[0]), float(color[1]), float(color[2])};
}

RenderBackend backendNamed(const std::string& name) {
  if (name == "vulkan") return RenderBackend::Vulkan;
  if (name == "cpu") return RenderBackend::Cpu;
  return RenderBackend::Auto;
}

struct ColoredByField {
  MeshPtr mesh;
  std::string name;
  FieldRange range;
};

// The mesh with its vertices coloured by the chosen field of `fields` (the first when none is).
ColoredByField colorByField(geobrush::Context& ctx, const MeshPtr& mesh, const VertexFields& fields,
                            std::string name) {
  if (const std::string why =
          fields.mismatch(mesh->surface, geobrush::derivedGeometryHash(ctx, mesh));
      !why.empty())
    throw NodeError::input("fields", why + " (input 'mesh')");
  if (name.empty()) {
    if (fields.columns.empty()) throw NodeError::input("fields", "it holds no field");
    name = fields.columns.front().first;
  }
  const auto* values = fields.find(name);
  if (!values) throw NodeError::param("field", "input 'fields' has no field '" + name + "'");
  ColoredByField colored{nullptr, name, fieldRange(*values)};
  colored.mesh = std::make_shared<const Mesh>(mesh->surface, fieldColors(*values, colored.range));
  return colored;
}

class RenderNode final : public Node {
 public:
  void compute(Context& ctx) override {
    std::vector<RenderItem> items;
    RenderItem main;
    main.mesh = ctx.in<Mesh>("mesh");
    std::optional<ColoredByField> colored;
    if (ctx.hasInput("fields")) {
      colored = colorByField(ctx, main.mesh, *ctx.in<VertexFields>("fields"),
                             ctx.param<std::string>("field"));
      main.mesh = colored->mesh;
    }
    main.color = toRgb(ctx.param<Vec3>("color"));
    main.wireframe = ctx.param<bool>("wireframe");
    items.push_back(main);
    if (ctx.hasInput("overlay")) {
      RenderItem overlay;
      overlay.mesh = ctx.in<Mesh>("overlay");
      overlay.color = toRgb(ctx.param<Vec3>("overlay_color"));
      overlay.wireframe = main.wireframe;
      items.push_back(overlay);
    }

    RenderOptions options;
    options.width = ctx.param<int>("width");
    options.height = ctx.param<int>("height");
    options.view.azimuthDeg = ctx.param<double>("azimuth");
    options.view.elevationDeg = ctx.param<double>("elevation");
    options.view.fovDeg = ctx.param<double>("fov");
    options.view.zoom = ctx.param<double>("zoom");
    options.background = toRgb(ctx.param<Vec3>("background"));
    options.backend = backendNamed(ctx.param<std::string>("backend"));
    if (const double radius = ctx.param<double>("focus_radius"); radius > 0)
      options.frame = RenderFrame{ctx.param<Vec3>("focus"), radius};

    RenderResult result = renderMeshes(items, options);
    if (colored && ctx.param<bool>("legend") &&
        !drawFieldLegend(result.image, colored->name, colored->range))
      ctx.warn("no font was found to draw the legend");
    auto image = std::make_shared<const Image>(std::move(result.image));
    if (!ctx.param<std::string>("path").empty())
      ctx.writeFile(ctx.path("path"),
                    [&](const std::filesystem::path& tmp) { writePng(*image, tmp); });
    ctx.out("image", image);
  }
};

void registerNodes(PluginRegistrar& registrar) {
  registrar.add(
      NodeTypeBuilder("geobrush.render", 1)
          .label("Render")
          .category("Output")
          .doc("Draws shaded meshes from an orbit camera into an image and a PNG file (Vulkan, "
               "or the CPU rasterizer).")
          .input<Mesh>("mesh", "The mesh to draw; its vertex colours are used if it has them.")
          .optionalInput<Mesh>("overlay", "A second mesh drawn in the same view.")
          .optionalInput<VertexFields>(
              "fields",
              "Fields on the mesh (emd_signal's, emd's, ...): the mesh is coloured by one of "
              "them, blue below zero, white at zero, red above (a dark-to-light ramp for a field "
              "of one sign), and the legend drawn.")
          .output<Image>("image", "The rendered picture.")
          .paramOutputPath("path", "render.png", "PNG file to write; empty writes no file.")
          .paramInt("width", 800, "Image width in pixels.")
          .range(kRenderSizeRange.min, kRenderSizeRange.max)
          .paramInt("height", 600, "Image height in pixels.")
          .range(kRenderSizeRange.min, kRenderSizeRange.max)
          .paramDouble("azimuth", 30, "Camera angle around +y, in degrees, from +z towards +x.")
          .range(kRenderAzimuthRange.min, kRenderAzimuthRange.max)
          .paramDouble("elevation", 20, "Camera angle above the xz plane, in degrees.")
          .range(kRenderElevationRange.min, kRenderElevationRange.max)
          .paramDouble("fov", 35, "Vertical field of view, in degrees.")
          .range(kRenderFovRange.min, kRenderFovRange.max)
          .paramDouble("zoom", 1, "Moves the camera closer than the fitted view when > 1.")
          .range(kRenderZoomRange.min, kRenderZoomRange.max)
          .paramVec3("focus", {0, 0, 0}, "The centre of the region to frame (with focus_radius).")
          .paramDouble("focus_radius", 0,
                       "Frames the ball of this radius around focus instead of the whole scene "
                       "(what lies outside is still drawn); 0 frames everything.")
          .range(0, kRenderFocusRadiusMax)
          .paramBool("wireframe", false, "Draw the triangle edges over the shading.")
          .paramString("field", "", "The field of 'fields' to colour by; empty: its first.")
          .paramBool("legend", true, "With 'fields': draw the colour bar and its range.")
          .paramVec3("color", {0.78, 0.78, 0.80}, "Colour of a mesh without vertex colours.")
          .range(0, 1)
          .paramVec3("overlay_color", {0.90, 0.60, 0.00}, "Colour of the overlay mesh.")
          .range(0, 1)
          .paramVec3("background", {1, 1, 1}, "Background colour.")
          .range(0, 1)
          .paramEnum("backend", "auto", {"auto", "vulkan", "cpu"},
                     "Vulkan (GPU or lavapipe) or the CPU rasterizer; auto is the CPU "
                     "rasterizer, the faster on every device measured.")
          .node<RenderNode>()
          .build());
}

}  // namespace
}  // namespace geobrush

GEOBRUSH_PLUGIN(geobrush::registerNodes)
