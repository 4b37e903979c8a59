#include <algorithm>
#include <memory>

#include "geobrush/cut_paste.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "intrinsic_param.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;

geobrush::BoundaryMode boundaryMode(const std::string& name) {
  if (name == "natural") return geobrush::BoundaryMode::Natural;
  if (name == "convex_hull") return geobrush::BoundaryMode::ConvexHull;
  if (name == "auto") return geobrush::BoundaryMode::Auto;
  if (name == "plane") return geobrush::BoundaryMode::Plane;
  throw NodeError::param("boundary",
                         "expected plane, natural, convex_hull or auto, not '" + name + "'");
}

std::shared_ptr<Parameterization> output(geobrush::CanvasPtr canvas,
                                         const geobrush::IntrinsicParamResult& result, bool base) {
  auto p = std::make_shared<Parameterization>();
  p->canvas = std::move(canvas);
  p->uv = base ? result.baseUv : result.featureUv;
  p->normal = base ? result.baseNormal : result.featureNormal;
  p->reversedFaces = base ? result.baseFlipped : result.featureFlipped;
  p->origin = result.origin;
  p->rotation = result.rotation;
  p->scale = result.scale;
  return p;
}

class IntrinsicParamNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto feature = ctx.in<Canvas>("feature");
    const auto base = ctx.in<Mesh>("base");
    geobrush::IntrinsicParamOptions options;
    options.lambda = ctx.param<double>("lambda");
    options.mu = ctx.param<double>("mu");
    if (!(options.lambda + options.mu > 0))
      throw NodeError::param("mu", "lambda and mu may not both be 0");
    options.boundary = boundaryMode(ctx.param<std::string>("boundary"));
    std::shared_ptr<const Parameterization> frame;
    if (ctx.hasInput("frame")) frame = ctx.in<Parameterization>("frame");
    options.frame = frame.get();
    geobrush::CanvasPtr baseCanvas;
    geobrush::IntrinsicParamResult result;
    try {
      result = geobrush::intrinsicParameterize(*feature, base->surface, options);
      baseCanvas = std::make_shared<const Canvas>(geobrush::canvasOfMesh(base));
    } catch (const geobrush::IntrinsicParamError& e) {
      throw NodeError::input(e.port(), e.what());
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("base", e.what());
    }
    if (result.planeOutsideVertices > 0)
      ctx.warn("boundary switched from plane to convex_hull: " +
               std::to_string(result.planeOutsideVertices) +
               " vertices of P^F fell outside P^B's boundary");
    else if (result.planeOutlineCrosses)
      ctx.warn(
          "boundary switched from plane to convex_hull: the loop's projection onto its "
          "plane crosses itself");
    if (result.outsideVertices > 0)
      ctx.warn(std::to_string(result.outsideVertices) +
               " vertices of P^F lie outside P^B's boundary; encoding extrapolates them");
    const auto flipped = std::count(result.baseFlipped.begin(), result.baseFlipped.end(), 1);
    if (flipped > 0)
      ctx.warn(std::to_string(flipped) +
               " faces of P^B are turned over in the domain: feature vertices over them may be "
               "encoded on the wrong sheet; a smoother or denser base avoids it");
    ctx.out("feature", output(feature, result, false));
    ctx.out("base", output(baseCanvas, result, true));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.intrinsic_param", 1)
          .label("Intrinsic Parameterization")
          .category("Cut and Paste")
          .doc("Maps a feature F and its base B to the plane with one boundary (topology-free cut "
               "and paste, Sec. 6.1): Desbrun-Meyer-Alliez's intrinsic map, lambda times the "
               "conformal plus mu times the authalic weights, inside; F.boundary[i] and B's "
               "vertex i share their uv, B's boundary split points lie on the chords between.")
          .input<Canvas>("feature", "F: the region cut out; any genus, one boundary loop.")
          .input<Mesh>("base",
                       "B over F: vertices 0..n-1 at F.boundary's positions, then added ones; "
                       "faces oriented like F's (cut_paste.hpp).")
          .optionalInput<Parameterization>(
              "frame",
              "A parameterization on F's source mesh (e.g. dem's): both outputs are moved by the "
              "similarity that best maps F's boundary uv onto its uv, and take its origin, "
              "rotation and scale.")
          .output<Parameterization>("feature", "P^F: uv per F vertex; normals of F's source.")
          .output<Parameterization>("base", "P^B: uv per B vertex over canvasOfMesh(B).")
          .paramDouble("lambda", 0.5, "Weight of the Dirichlet (conformal, cot) energy.")
          .range(0.0, 1e6)
          .paramDouble("mu", 0.5, "Weight of the chi (authalic) energy.")
          .range(0.0, 1e6)
          .paramEnum("boundary", "auto", {"auto", "plane", "natural", "convex_hull"},
                     "plane: the boundary projected on its best-fit plane; natural: the boundary "
                     "of B flattened with a free boundary (LSCM); convex_hull: the natural "
                     "boundary's convex hull; auto (the default): plane, or convex_hull when F "
                     "leaves B's boundary or the projected loop crosses itself (a loop over "
                     "handles: the walk on the target needs a simple outline). The interiors "
                     "always follow the intrinsic map.")
          .node<IntrinsicParamNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
