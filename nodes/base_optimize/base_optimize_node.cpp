#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "base_optimize.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::TriMesh;

std::shared_ptr<geobrush::Metrics> report(const geobrush::BaseOptimizeResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["loop_vertices"] = result.loopVertices;
  v["reference_length"] = result.referenceLength;
  v["target_length"] = result.targetLength;
  v["splits"] = result.splits;
  v["resplits"] = result.resplits;
  v["slices"] = result.slices;
  v["collapses"] = result.collapses;
  v["needles_left"] = result.needlesLeft;
  v["min_angle_before_deg"] = result.minAngleBeforeDeg;
  v["min_angle_after_deg"] = result.minAngleAfterDeg;
  v["vertices"] = double(result.base.n_vertices());
  v["faces"] = double(result.base.n_faces());
  return metrics;
}

// The length of the mesh's boundary (the bases' one loop).
double loopLength(const TriMesh& mesh) {
  double length = 0;
  for (auto h : mesh.halfedges())
    if (mesh.is_boundary(h)) length += mesh.calc_edge_length(h);
  return length;
}

class BaseOptimizeNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto base = ctx.in<Mesh>("base");
    geobrush::BaseOptimizeOptions options;
    options.epsilon = ctx.param<double>("epsilon");
    options.capAngleDeg = ctx.param<double>("cap_angle_deg");
    options.aspectThreshold = ctx.param<double>("aspect_threshold");
    options.smoothIterations = ctx.param<int>("smooth_iterations");
    const bool referenced = ctx.hasInput("reference");
    if (referenced) {
      const TriMesh& reference = ctx.in<Mesh>("reference")->surface;
      const double scale = loopLength(base->surface) / loopLength(reference);
      options.referenceLength = geobrush::meanEdgeLength(reference) * scale;
      if (!(options.referenceLength > 0.0) || !std::isfinite(options.referenceLength))
        throw NodeError::input("reference",
                               "its mean edge length, scaled to this loop, is not a positive "
                               "length");
    }
    geobrush::BaseOptimizeResult result;
    try {
      result = geobrush::optimizeBase(base->surface, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("base", e.what());
    } catch (const geobrush::BaseGrowthError& e) {
      const std::string message = std::string(e.what()) + "; raise epsilon";
      if (referenced) throw NodeError::input("reference", message + " or use a coarser reference");
      throw NodeError::param("epsilon", message);
    }
    if (result.needlesLeft > 0)
      ctx.warn(std::to_string(result.needlesLeft) +
               " faces end with an aspect ratio <= " + std::to_string(options.aspectThreshold) +
               ": needles whose collapse would flip a face, break the disc or move the loop, "
               "or made by the smoothing");
    ctx.out("base", std::make_shared<const Mesh>(result.base));
    ctx.out("report", report(result));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.base_optimize", 1)
          .label("Base Optimize")
          .category("Cut and Paste")
          .doc("The base surface B from a boundary triangulation B0 (topology-free cut-and-paste, "
               "Sec. 5.2), in this order with B0's loop fixed: 1) split the longest edge at its "
               "midpoint until every edge is shorter than epsilon times the reference (Eq. 2); "
               "2) slice caps (an angle above cap_angle_deg, shortest edge at least "
               "aspect_threshold times the longest) at the apex's foot on the longest edge; "
               "3) collapse the shortest edge of faces with aspect ratio <= aspect_threshold "
               "(into a boundary end, else to the midpoint; only where OpenMesh allows it, no "
               "normal flips and no edge reaches the Eq. 2 bound); 4) umbrella-smooth the "
               "interior, by default to rest (the paper's few passes leave a dense base "
               "almost as jagged as B0: the detail encoded over it then folds where it is "
               "moved onto another base). Edges smoothing stretched past the bound are split "
               "again. Refuses "
               "densities needing more than 2,000,000 vertices.")
          .input<Mesh>("base",
                       "B0: vertices 0..n-1 its boundary loop, in the order of its "
                       "boundary halfedges (min_area_triangulate's output).")
          .optionalInput<Mesh>("reference",
                               "The source base B^S: its mean edge length, scaled by the ratio "
                               "of the two loops' lengths (the paste's scale), is the reference "
                               "(Sec. 7.1, for a target base). Without it the reference is l_min, "
                               "B0's shortest edge, diagonals included (Sec. 5.2).")
          .output<Mesh>("base",
                        "B: vertices 0..n-1 are B0's, bit-identical and in order; then the "
                        "others. Points added on the boundary lie on B0's boundary edges; the "
                        "boundary halfedges still run from vertex i towards vertex i + 1.")
          .output<geobrush::Metrics>(
              "report",
              "loop_vertices, reference_length, target_length (epsilon x reference), splits, "
              "resplits (after smoothing), slices, collapses, needles_left, "
              "min_angle_before_deg, min_angle_after_deg, vertices, faces.")
          .paramDouble("epsilon", 2.0, "Eq. 2: every edge ends shorter than epsilon x reference.")
          .range(0.05, 1000.0)
          .paramDouble("cap_angle_deg", 160.0,
                       "A face with a larger angle that is no needle is a cap and is sliced; "
                       "180 slices none.")
          .range(90.0, 180.0)
          .paramDouble("aspect_threshold", 0.1,
                       "tau: faces whose aspect ratio (short over long side of the smallest "
                       "rectangle on one of their edges; equilateral 0.87, right isosceles 1) is "
                       "at most tau are collapsed; a face whose shortest edge is below tau x its "
                       "longest is a needle, not a cap.")
          .range(0.0, 0.5)
          .paramInt("smooth_iterations", -1,
                    "Jacobi umbrella passes over the interior vertices; -1: to rest (the "
                    "passes' limit, one sparse solve).")
          .range(-1, 1000)
          .node<BaseOptimizeNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
