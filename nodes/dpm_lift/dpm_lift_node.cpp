#include <cmath>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dpm_lift.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;

// A map the lift can read: a canvas with faces, one finite uv per vertex.
void checkMap(std::string_view port, const Parameterization& map) {
  if (!map.canvas || map.canvas->surface.n_faces() == 0)
    throw NodeError::input(port, "the map's canvas has no faces");
  if (map.uv.size() != map.canvas->surface.n_vertices())
    throw NodeError::input(port, "the map has not one uv per canvas vertex");
  for (const auto& u : map.uv)
    if (!u.allFinite()) throw NodeError::input(port, "the map has a non-finite uv");
  if (!map.origin.point.allFinite() || !map.origin.normal.allFinite())
    throw NodeError::input(port, "the map's origin frame is not finite");
}

// All source canvas vertices, or only those a paste of the connected region reads.
std::vector<int> verticesToLift(Context& ctx, std::size_t count) {
  std::vector<int> vertices;
  if (ctx.hasInput("region")) {
    vertices = ctx.in<geobrush::Region2D>("region")->draftSupport;
    for (int v : vertices)
      if (v < 0 || std::size_t(v) >= count)
        throw NodeError::input("region", "its draft support names vertex " + std::to_string(v) +
                                             ", which the source canvas does not have");
    return vertices;
  }
  for (std::size_t v = 0; v < count; ++v)
    vertices.push_back(int(v));
  return vertices;
}

class DpmLiftNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    checkMap("source", *source);
    checkMap("target", *target);
    if (!std::isfinite(target->scale) || !(target->scale > 0))
      throw NodeError::input("target", "its scale must be a finite number > 0");
    geobrush::LiftOptions options;
    if (ctx.param<std::string>("offset_direction") == "surface")
      options.direction = geobrush::OffsetDirection::Surface;
    const std::vector<int> vertices = verticesToLift(ctx, source->uv.size());
    const auto locator = geobrush::derivedLocator(ctx, "target");
    const geobrush::LiftResult lift =
        geobrush::liftVertices(*source, *target, *locator, vertices, options);
    if (!lift.extrapolated.empty()) {
      std::string message = std::to_string(lift.extrapolated.size());
      message += " source vertices (the first is vertex ";
      message += std::to_string(lift.extrapolated.front());
      message +=
          ") map outside the target canvas; their places were extrapolated from its "
          "outline";
      ctx.warn(message);
    }
    // Vertices the region does not read keep their source positions, as gc_warp's do.
    geobrush::TriMesh draft = source->canvas->surface;
    for (std::size_t k = 0; k < vertices.size(); ++k)
      draft.set_point(geobrush::TriMesh::VertexHandle(vertices[k]),
                      geobrush::toPoint(lift.points[k]));
    ctx.out("draft", std::make_shared<const Mesh>(draft));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.dpm_lift", 1)
            .label("Projective Lift")
            .category("Preprocess")
            .doc("The 3D retrieval of GPU texture cloning: every source canvas vertex placed at "
                 "p = X_T(u) + scale h d, X_T(u) the target canvas point at its uv, h its offset "
                 "above the source map's plane: the draft the paste reads, in place of a cage "
                 "warp.")
            .input<Parameterization>("source", "The source map (geobrush.dpm's).")
            .input<Parameterization>("target",
                                     "The target map in the same domain (geobrush.dpm_target's).")
            .optionalInput<geobrush::Region2D>(
                "region",
                "When connected, only the vertices a paste of this region reads (its draft "
                "support) are lifted; the others keep their source positions.")
            .output<Mesh>("draft",
                          "The source canvas surface, same connectivity, with the lifted points.")
            .paramEnum("offset_direction", "plane", {"plane", "surface"},
                       "d: the target view normal (plane) or the target's vertex normals "
                       "interpolated at X_T(u) (surface).")
            .node<DpmLiftNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
