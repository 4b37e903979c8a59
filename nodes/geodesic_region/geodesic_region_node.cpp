#include <memory>

#include "geobrush/canvas.hpp"
#include "geobrush/cut_paste.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "geodesic_region.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;

std::shared_ptr<geobrush::Metrics> report(const geobrush::GeodesicRegionResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["closing_gap"] = result.loop.gap;
  v["closing_gap_relative"] = result.loop.gap / result.loop.length;
  v["closing_stretch"] = result.loop.stretch.norm();
  v["closing_bend_deg"] = result.loop.bend * result.loop.length * 180 / 3.141592653589793;
  v["faces"] = double(result.region.sourceFace.size());
  v["crossed_faces"] = double(result.crossed.size());
  v["loop_length"] = result.loop.length;
  v["corners"] = double(result.loop.corner.size());
  v["vertices_passed"] = result.loop.vertices;
  return metrics;
}

class GeodesicRegionNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto target = ctx.in<Mesh>("target");
    const auto base = ctx.in<Parameterization>("base");
    const auto placement = ctx.in<Parameterization>("placement");
    const geobrush::GeodesicRegionOptions options;
    geobrush::GeodesicRegionResult result;
    try {
      result = geobrush::geodesicRegion(target, *base, *placement, options);
    } catch (const geobrush::GeodesicRegionError& e) {
      throw NodeError::input(e.option(), e.what());
    }
    const double relative = result.loop.gap / result.loop.length;
    if (relative > options.gapWarning)
      ctx.warn("the walked loop misses closing by " + std::to_string(100 * relative) +
               "% of its length (the target curves under the base); its last side was aimed at "
               "its first corner");
    auto path = std::make_shared<geobrush::SurfacePath>();
    path->mesh = target;
    path->face = result.loop.cornerFace;
    path->point = result.loop.corner;
    path->closingGap = result.loop.gap;
    path->scale = placement->scale;
    ctx.out("report", report(result));
    ctx.out("path", std::move(path));
    ctx.out("region", std::make_shared<const geobrush::Canvas>(std::move(result.region)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.geodesic_region", 1)
            .label("Geodesic Region")
            .category("Cut and Paste")
            .doc("Places the source base's boundary on the target (topology-free cut and paste, "
                 "geodesic walk): from the placement's origin, a straightest geodesic "
                 "(Polthier-Schmies) toward the first boundary corner's uv, then one per side, "
                 "lambda times the side's uv length, turning at each corner by the boundary's "
                 "corner angle. Where the target curves that loop misses its first corner (the "
                 "curvature it encloses turns its heading): it is walked again with a uniform "
                 "extra turn per unit length and side lengths stretched by their direction that "
                 "close it (the least change, by Newton steps), "
                 "and its last side aimed at the first corner; a miss over 5% of the loop's "
                 "length is warned about. "
                 "The region is the faces the loop crosses plus those it encloses on its inner "
                 "side (the side its uv orientation gives).")
            .input<Mesh>("target", "The target surface.")
            .input<Parameterization>(
                "base",
                "P^SB: the source base's parameterization (its canvas is the base itself), uv in "
                "the source's shared domain.")
            .input<Parameterization>(
                "placement",
                "The target DEM on this target: its origin frame (axes already turned by the "
                "angle) and scale lambda place the domain on the target.")
            .output<geobrush::Canvas>("region", "F^T: the walked region on the target, one loop.")
            .output<geobrush::SurfacePath>(
                "path",
                "The walked corners, one per base boundary corner, with their faces, the "
                "closing gap and lambda.")
            .output<geobrush::Metrics>(
                "report",
                "closing_gap (mesh units: how far the polygon walked as it is misses closing), "
                "closing_gap_relative (to the loop's length lambda x perimeter), "
                "closing_stretch and closing_bend_deg (how much the side lengths and the total "
                "turn change to close it), faces (the region's), crossed_faces, loop_length, "
                "corners, "
                "vertices_passed.")
            .node<GeodesicRegionNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
