#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/border_loop.hpp"
#include "geobrush/node.hpp"
#include "geobrush/point_pairs.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "template_icp.hpp"

namespace {

using geobrush::BorderLoop;
using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

std::vector<Eigen::Vector3d> borderPoints(const BorderLoop& border) {
  const std::string problem =
      !border.mesh || border.vertex.empty()
          ? "the border loop is empty"
          : geobrush::borderLoopProblem(border.mesh->surface, border.vertex);
  if (!problem.empty()) throw NodeError::input("border", problem);
  std::vector<Eigen::Vector3d> points;
  for (int v : border.vertex)
    points.push_back(geobrush::pointOf(border.mesh->surface, v));
  return points;
}

// The template's vertices in a kd-tree, kept by the framework while the template is unchanged.
std::shared_ptr<const geobrush::PointNeighbours> templateTree(Context& ctx, const Mesh& mesh) {
  if (mesh.surface.n_vertices() == 0) throw NodeError::input("template", "the template is empty");
  try {
    return ctx.derived("point_neighbours", {"template"}, 0, [&] {
      return std::make_shared<const geobrush::PointNeighbours>(
          geobrush::vertexPoints(mesh.surface));
    });
  } catch (const std::invalid_argument& e) {
    throw NodeError::input("template", std::string("the template's ") + e.what());
  }
}

// Pairs whose template vertex an earlier pair already has.
std::size_t pairsOnASharedVertex(const geobrush::PointPairs& pairs) {
  std::vector<int> vertices = pairs.templateVertex;
  std::sort(vertices.begin(), vertices.end());
  return std::size_t(vertices.end() - std::unique(vertices.begin(), vertices.end()));
}

std::shared_ptr<const geobrush::Metrics> report(const geobrush::TemplateIcpResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  metrics->values = {{"rms_before", result.rmsBefore},
                     {"rms_after", result.rmsAfter},
                     {"rotation_degrees", result.motion.angleDegrees()},
                     {"translation", result.motion.translation.norm()},
                     {"iterations", result.iterations},
                     {"pairs_kept", double(result.pairs.size()) - result.rejected},
                     {"pairs_rejected", result.rejected},
                     {"rms_all_pairs", result.rmsAllPairs},
                     {"started_where_placed", result.start == 1 ? 1.0 : 0.0}};
  return metrics;
}

class TemplateIcpNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("template");
    const auto border = ctx.in<BorderLoop>("border");
    const auto points = borderPoints(*border);
    const auto tree = templateTree(ctx, *mesh);
    geobrush::TemplateIcpOptions options;
    options.iterations = int(ctx.param<int>("iterations"));
    options.reject = ctx.param<double>("reject");
    if (ctx.param<bool>("prealign")) {
      options.initial =
          geobrush::frameAlignment(mesh->surface, border->mesh->surface, border->vertex);
      options.otherStarts = {geobrush::RigidMotion()};
    }
    geobrush::TemplateIcpResult result;
    try {
      options.explicitPairs =
          geobrush::icpPairsFromRows(ctx.param<std::vector<double>>("explicit_pairs"));
      result = geobrush::alignTemplate(*tree, points, options);
    } catch (const geobrush::TemplateIcpError& e) {
      if (e.option() == "template" || e.option() == "border")
        throw NodeError::input(e.option(), e.what());
      throw NodeError::param(e.option(), e.what());
    }
    auto pairs = std::make_shared<geobrush::PointPairs>();
    for (const auto& pair : result.pairs) {
      pairs->border.push_back(points[std::size_t(pair.border)]);
      pairs->templateVertex.push_back(pair.templateVertex);
    }
    if (const std::size_t shared = pairsOnASharedVertex(*pairs); shared > 0)
      ctx.warn(std::to_string(shared) +
               " border points pair with a template vertex another one took: the template is "
               "coarser than the border, and the warp keeps one pair per vertex (raise the "
               "template's resolution)");
    ctx.out("template",
            std::make_shared<const Mesh>(geobrush::moveRigidly(mesh->surface, result.motion),
                                         mesh->vertexColors));
    ctx.out("pairs", std::move(pairs));
    ctx.out("report", report(result));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.template_icp", 1)
            .label("Template ICP")
            .category("Inpainting")
            .doc("Moves a template rigidly onto a hole's border (surface inpainting section 4.1): "
                 "pairs each border point with its closest template vertex, drops outlier pairs, "
                 "applies the rigid motion that minimizes the pairs' squared distances (Kabsch) "
                 "and iterates; or solves once from explicit pairs.")
            .input<Mesh>("template", "The template T: a primitive or a part of a mesh.")
            .input<BorderLoop>("border", "The hole's border B.")
            .output<Mesh>("template", "T moved rigidly onto the border: T'.")
            .output<geobrush::PointPairs>(
                "pairs",
                "Per border point, in loop order: b_i and its closest vertex of T' "
                "(or the explicit pairs); outliers stay out of the fit only.")
            .output<geobrush::Metrics>("report",
                                       "RMS pair distance before and after (pairs "
                                       "fitted) and of every pair after, rotation "
                                       "degrees, translation, iterations, pairs kept "
                                       "and rejected, started_where_placed.")
            .paramInt("iterations", 5, "At most this many pair-and-move rounds (\"a few\").")
            .range(0, 1000)
            .paramDouble("reject", 3.0,
                         "Leave pairs farther apart than this multiple of the median pair "
                         "distance out of the fit; 0 keeps every pair, otherwise at least 1.")
            .range(0, 1e9)
            .paramBool("prealign", true,
                       "Start from the template's centroid on the border's and its mean normal "
                       "turned onto the surface's along the border, so that a primitive made at "
                       "the origin needs no placing by hand, and also where the template is; "
                       "the start whose fit ends closer to every border point wins "
                       "(started_where_placed). Off: start where the template is.")
            .paramList("explicit_pairs", int(geobrush::kIcpPairRowSize), {},
                       "Rows of border index, template vertex: when given, the motion is solved "
                       "once from these pairs. Empty: pairs found automatically.")
            .node<TemplateIcpNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
