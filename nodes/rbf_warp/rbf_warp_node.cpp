#include <memory>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "rbf_warp.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::PointPairs;

// Beyond this the warp's constraints hold to fewer than about 4 digits of the displacement.
constexpr double kIllConditioned = 1e12;

std::shared_ptr<geobrush::Metrics> report(const geobrush::RbfWarpResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["constraints"] = double(result.constraintPair.size());
  v["duplicates_dropped"] = result.duplicatesDropped;
  v["condition_number"] = result.conditionNumber;
  v["t_max"] = result.tMax;
  v["max_residual_relative"] = result.maxResidual;
  v["max_residual_all_pairs_relative"] = result.maxResidualAllPairs;
  v["kept_vertices"] = double(result.mesh.n_vertices());
  v["kept_faces"] = double(result.mesh.n_faces());
  v["constraints_kept"] = result.constraintsKept;
  return metrics;
}

class RbfWarpNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto templ = ctx.in<Mesh>("template");
    const auto pairs = ctx.in<PointPairs>("pairs");
    geobrush::RbfWarpOptions options;
    options.k = ctx.param<int>("k");
    options.tMax = ctx.param<double>("t_max");
    options.reg = ctx.param<double>("reg");
    options.stride = ctx.param<int>("stride");
    options.crop = ctx.param<bool>("crop");
    options.snapBoundary = ctx.param<bool>("snap_boundary");
    options.tMaxFromBorder = ctx.param<std::string>("t_max_auto") == "border_radius";
    options.straightDistance = ctx.param<std::string>("distance") == "straight";
    if (ctx.param<std::string>("kernel") == "scodef") options.kernel = geobrush::RbfKernel::Scodef;
    // The geodesic delta's graph over the template's vertices, shared with any node that asks
    // for the same template and k.
    const auto graph = geobrush::derivedVertexGraph(ctx, "template", options.k);
    geobrush::RbfWarpResult result;
    try {
      result = geobrush::rbfWarp(templ->surface, *graph, *pairs, options);
    } catch (const geobrush::RbfWarpError& e) {
      throw NodeError::input(e.option(), e.what());
    }
    if (result.conditionNumber > kIllConditioned)
      ctx.warn("cond(A) = " + std::to_string(result.conditionNumber) +
               ": the warp's system is near-singular; raise reg or stride, or lower t_max");
    if (result.duplicatesDropped > 0)
      ctx.warn(std::to_string(result.duplicatesDropped) +
               " pairs share a template vertex with an earlier one and do not constrain the warp");
    ctx.out("template", std::make_shared<const Mesh>(result.mesh));
    ctx.out("report", report(result));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.rbf_warp", 1)
            .label("RBF Warp")
            .category("Inpainting")
            .doc("Warps an aligned template so that each paired vertex t_b_i lands on its border "
                 "point b_i (Freeform surface inpainting, section 4.2): d(x) = sum_i "
                 "phi(delta(t_b_i, x)) D_i with phi(t) = exp(-(t/t_max)^2), delta the geodesic "
                 "along the template's symmetric kNN graph and A D = b - t_b (Eqs. 4-6); Eq. 3's "
                 "shape function is 1. Then keeps the part of the template on the hole's side of "
                 "L, the shortest edge path through the t_b_i in order: the faces reached from the "
                 "one nearest the border's centroid without crossing L.")
            .input<Mesh>("template", "T': the template, aligned to the hole (template_icp).")
            .input<PointPairs>("pairs", "(b_i, t_b_i) in the border's order.")
            .output<Mesh>("template", "T'': the warped template, cropped to the hole.")
            .output<geobrush::Metrics>(
                "report",
                "constraints (K), duplicates_dropped, condition_number (of A with reg), t_max, "
                "max_residual_relative (max |t_b_i - b_i| over the constraints after the warp, "
                "relative to the template's bounding-box diagonal), "
                "max_residual_all_pairs_relative, kept_vertices, kept_faces, constraints_kept.")
            .paramInt("k", 8, "Neighbours per vertex in the kNN graph of the geodesic delta.")
            .range(1, 64)
            .paramDouble("t_max", 0.0, "phi's width; 0: the template's bounding-box diagonal.")
            .range(0, 1e30)
            .paramDouble("reg", 0.0,
                         "Tikhonov term: A's eigenvalues moved away from 0 by reg (A + reg I "
                         "where A is positive definite); a better-conditioned system, "
                         "constraints met up to reg |D|.")
            .range(0, 1e30)
            .paramInt("stride", 1, "Every stride-th pair is a constraint (thins dense ones).")
            .range(1, 1000000)
            .paramBool("crop", true, "Keep only the template's part on the hole side of L.")
            .paramEnum("t_max_auto", "template_diagonal", {"template_diagonal", "border_radius"},
                       "t_max when the param is 0: the template's bounding-box diagonal (the "
                       "paper's), or the border's radius, a kernel the size of the hole [ours].")
            .paramBool("snap_boundary", true,
                       "With crop: lay the cropped boundary onto the border polyline (each t_b_i "
                       "on b_i, the path between along the segment), so a weld shares every "
                       "seam vertex [ours].")
            .paramEnum("distance", "graph", {"graph", "straight"},
                       "delta: the kNN graph's geodesic (the paper's), or the straight distance "
                       "between template vertices, which equals it on a flat template without "
                       "the graph's direction error [ours].")
            .paramEnum("kernel", "gaussian", {"gaussian", "scodef"},
                       "phi: the paper's Gaussian exp(-(t/t_max)^2), or SCODEF's cubic 1 - 3s^2 + "
                       "2s^3 (s = t/t_max, 0 beyond), the point constraints the paper starts from "
                       "(Eqs. 1-2), for comparison.")
            .node<RbfWarpNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
