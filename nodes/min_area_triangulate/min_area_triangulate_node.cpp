#include <memory>
#include <stdexcept>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "min_area_triangulate.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

std::shared_ptr<geobrush::Metrics> report(const geobrush::MinAreaResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["objective"] = result.objective;
  v["area"] = result.area;
  v["interior_edge_length"] = result.interiorEdgeLength;
  v["loop_vertices"] = double(result.base.n_vertices());
  v["triangles"] = double(result.base.n_faces());
  v["self_intersections"] = double(result.selfIntersections);
  v["degenerate_triangles"] = double(result.degenerate);
  return metrics;
}

class MinAreaTriangulateNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto canvas = ctx.in<Canvas>("canvas");
    geobrush::MinAreaOptions options;
    options.objective = ctx.param<std::string>("objective") == "perimeter"
                            ? geobrush::TriangulationObjective::Perimeter
                            : geobrush::TriangulationObjective::Area;
    geobrush::MinAreaResult result;
    try {
      result = geobrush::minAreaTriangulate(*canvas, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("canvas", e.what());
    }
    if (result.selfIntersections > 0)
      ctx.warn("the base intersects itself: " + std::to_string(result.selfIntersections) +
               " pairs of its faces meet; the boundary may not be triangulable without folds");
    if (result.degenerate > 0)
      ctx.warn(std::to_string(result.degenerate) +
               " triangles of the base have their corners on one line: the loop leaves no "
               "other way to span it");
    ctx.out("base", std::make_shared<const Mesh>(result.base));
    ctx.out("report", report(result));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.min_area_triangulate", 1)
          .label("Min-Area Triangulate")
          .category("Cut and Paste")
          .doc(
              "The base B0 of a feature region (topology-free cut-and-paste, Sec. 5.1): the "
              "triangulation of the region's boundary loop over its own vertices that "
              "minimizes the total triangle area (Eq. 1), by the O(n^3) dynamic programme "
              "(ties to the smallest split vertex). A triangle whose corners lie on one line (a "
              "loop running straight along mesh edges) is used only where nothing else spans "
              "the loop: it would fold onto its neighbours. Vertex i is the loop's vertex i at its "
              "position, faces are oriented like the region's. Loops of more than 2000 "
              "vertices are refused (O(n^2) memory, O(n^3) time). Warns when the base "
              "intersects itself.")
          .input<Canvas>("canvas", "The feature region F, bounded by one loop.")
          .output<Mesh>("base",
                        "B0: vertex i at F.boundary[i], n - 2 faces whose boundary halfedges "
                        "run from vertex i to i + 1.")
          .output<geobrush::Metrics>(
              "report",
              "objective (the minimized sum), area (B0's total area), interior_edge_length "
              "(the total length of its n - 3 interior edges), loop_vertices, triangles, "
              "self_intersections (pairs of faces that meet), degenerate_triangles.")
          .paramEnum("objective", "area", {"area", "perimeter"},
                     "area: the sum of the triangles' areas (Eq. 1). perimeter: the sum of the "
                     "triangles' perimeters, which is the loop's length plus twice the length "
                     "of the interior edges: the triangulation of least total edge length.")
          .node<MinAreaTriangulateNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
