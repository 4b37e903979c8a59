#include <memory>
#include <stdexcept>
#include <string>

#include "geobrush/domain_locator.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "texture_raster_vulkan.hpp"
#include "texture_roi.hpp"

namespace {

using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Region2D;
using geobrush::Strokes;
using geobrush::TextureKernel;

// "auto" is the CPU twin on every device: the kernel's one submission, uploads and readback cost
// more than the twin's pass on lavapipe and on a discrete GPU alike (BENCHMARKS.md, "Vulkan on a
// GPU"). Both give the same texture bit for bit.
TextureKernel chooseKernel(const std::string& choice) {
  if (choice == "auto" || choice == "cpu") return TextureKernel::Cpu;
  if (choice != "vulkan")
    throw NodeError::param("kernel", "'" + choice + "' is not one of: auto, cpu, vulkan");
  if (geobrush::textureRasterVulkanAvailable()) return TextureKernel::Vulkan;
  throw NodeError::param("kernel", "vulkan needs a Vulkan device, and there is none: " +
                                       geobrush::textureRasterVulkanUnavailableReason());
}

// A texture of the canvas on `port`; its errors name that port, and a failing Vulkan call (the
// only std::runtime_error a rasterization throws) the kernel.
template <typename Make>
auto derive(std::string_view port, const Make& make) {
  try {
    return make();
  } catch (const NodeError&) {
    throw;
  } catch (const geobrush::TextureRoiError& e) {
    throw NodeError::input(port, e.what());
  } catch (const std::runtime_error& e) {
    throw NodeError::param("kernel", e.what());
  }
}

// Painting changes only the strokes: both textures are derived data, kept while the
// parameterizations, the size and the kernel stay the same; a dab only redoes the copy.
class TextureRoiNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto strokes = ctx.in<Strokes>("strokes");
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    geobrush::TextureRoiOptions options;
    options.textureSize = int(ctx.param<int>("texture_size"));
    options.kernel = chooseKernel(ctx.param<std::string>("kernel"));
    const geobrush::Hash key = geobrush::Hasher()
                                   .u64(std::uint64_t(options.textureSize))
                                   .u64(options.kernel == TextureKernel::Vulkan)
                                   .digest();
    const auto sourceSide = derive("source", [&] {
      return ctx.derived("texture_roi_source", {"source"}, key,
                         [&] { return geobrush::textureSourceSide(*source, options); });
    });
    const auto targetSide = derive("target", [&] {
      return ctx.derived("texture_roi_target", {"source", "target"}, key, [&] {
        return geobrush::textureTargetSide(*target, sourceSide->texture.grid, options.kernel);
      });
    });
    const auto locator = geobrush::derivedLocator(ctx, "source");
    geobrush::TextureRoiResult result =
        geobrush::copyTexels(*strokes, *source, *target, *sourceSide, *targetSide, *locator);
    warnAboutDabs(ctx, result, *strokes);
    ctx.out("region", std::make_shared<const Region2D>(std::move(result.region)));
  }

 private:
  static void warnAboutDabs(Context& ctx, const geobrush::TextureRoiResult& result,
                            const Strokes& strokes) {
    if (!result.dabsOutside.empty()) {
      std::string message = std::to_string(result.dabsOutside.size());
      message += " dabs paint no texel that both canvases cover; they change nothing";
      ctx.warn(message);
    }
    if (result.region.empty() && !strokes.dabs.empty())
      ctx.warn("the strokes select no source vertex: the target stays unchanged");
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.texture_roi", 1)
            .label("Texture Region of Interest")
            .category("Real-time")
            .doc("The region of interest as a GPU texture copy (Mesh Geometric Editing Approach "
                 "Based on GPU Texture): both canvases rasterized into N x N face-id and "
                 "barycentric textures over the shared domain, the painted texels covered on "
                 "both copied. A drop-in for geobrush.roi: the same ports and Region2D, on the "
                 "texel grid.")
            .input<Strokes>("strokes", "The dabs painted so far.")
            .input<Parameterization>("source", "The source canvas and its map.")
            .input<Parameterization>("target", "The target canvas in the same domain.")
            .output<Region2D>("region", "The copied texels, R_in and the covered target vertices.")
            .paramInt("texture_size", 512, "Texels along each side of both textures (N).")
            .range(16, 4096)
            .paramEnum("kernel", "auto", {"auto", "cpu", "vulkan"},
                       "Where the textures are rasterized: vulkan (the Vulkan device, an error "
                       "without one), cpu, or auto (cpu, the faster on every device measured); "
                       "both give the same textures bit for bit.")
            .node<TextureRoiNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
