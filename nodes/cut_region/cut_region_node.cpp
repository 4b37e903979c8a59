#include <memory>

#include "cut_region.hpp"
#include "geobrush/border_loop.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

// The painted mesh vertices, or none (an existing hole is picked) where neither input is connected.
geobrush::CutRegionOptions options(Context& ctx, const Mesh& mesh) {
  geobrush::CutRegionOptions o;
  const auto near = ctx.param<geobrush::Vec3>("near");
  o.near = Eigen::Vector3d(near[0], near[1], near[2]);
  const bool canvas = ctx.hasInput("canvas"), strokes = ctx.hasInput("strokes");
  if (!canvas && !strokes) return o;
  if (!canvas) throw NodeError::input("canvas", "strokes need the canvas they were painted on");
  if (!strokes) throw NodeError::input("strokes", "a canvas is connected but no strokes");
  auto painting = geobrush::paintedVertices(mesh, *ctx.in<geobrush::Parameterization>("canvas"),
                                            *ctx.in<geobrush::Strokes>("strokes"));
  if (painting.reachesCanvasBorder)
    ctx.warn("the painting reaches the canvas' border: the mesh beyond the canvas is not cut");
  o.painted = std::move(painting.painted);
  return o;
}

std::shared_ptr<geobrush::Metrics> report(const geobrush::CutRegionResult& r,
                                          std::size_t inputVertices) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["painted_vertices"] = double(r.paintedVertices);
  v["removed_vertices"] = double(inputVertices - r.keptVertex.size());
  v["removed_faces"] = double(r.removedFace.size());
  v["cleaned_faces"] = double(r.cleanedFaces);
  v["border_vertices"] = double(r.border.size());
  return metrics;
}

// The colours of `vertices` of the input, where it has colours.
std::vector<geobrush::Rgb> colorsOf(const Mesh& mesh, const std::vector<int>& vertices) {
  std::vector<geobrush::Rgb> colors;
  if (!mesh.vertexColors.empty())
    for (int v : vertices)
      colors.push_back(mesh.vertexColors[std::size_t(v)]);
  return colors;
}

class CutRegionNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    geobrush::CutRegionResult result;
    try {
      result = geobrush::cutRegion(mesh->surface, options(ctx, *mesh));
    } catch (const geobrush::CutRegionError& e) {
      if (e.port() == "near") throw NodeError::param(e.port(), e.what());
      throw NodeError::input(e.port(), e.what());
    }
    auto holed = std::make_shared<const Mesh>(result.mesh, colorsOf(*mesh, result.keptVertex));
    auto border = std::make_shared<geobrush::BorderLoop>();
    border->mesh = holed;
    border->vertex = result.border;
    ctx.out("mesh", holed);
    ctx.out("border", std::move(border));
    ctx.out("removed",
            std::make_shared<const Mesh>(result.removed, colorsOf(*mesh, result.removedVertex)));
    ctx.out("report", report(result, mesh->surface.n_vertices()));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.cut_region", 1)
            .label("Cut Region")
            .category("Inpainting")
            .doc("Removes the damaged region to repair (Freeform surface inpainting, Fig. 2 stage "
                 "1): every face with a painted vertex goes, then islands the region cut off and "
                 "the smaller wedges at vertices the cut pinched, so the rest is one manifold "
                 "piece with one new boundary loop. Without canvas and strokes it picks an "
                 "existing hole instead and removes nothing.")
            .input<Mesh>("mesh", "The mesh to cut: one manifold component.")
            .optionalInput<geobrush::Parameterization>(
                "canvas",
                "A canvas on the mesh with its map (e.g. geobrush.dem, keep_holes) in "
                "the domain the strokes are painted in.")
            .optionalInput<geobrush::Strokes>(
                "strokes", "The painted region: the mesh vertices whose canvas uv it paints.")
            .output<Mesh>("mesh", "The holed mesh, the input's vertices and faces in their order.")
            .output<geobrush::BorderLoop>("border", "The hole's boundary loop on the output mesh.")
            .output<Mesh>("removed",
                          "The removed faces as a mesh of their own, in their order "
                          "(the ground truth of a test cut); empty when none.")
            .output<geobrush::Metrics>(
                "report",
                "painted_vertices, removed_vertices (not in the "
                "output), removed_faces, cleaned_faces (unpainted faces removed with them), "
                "border_vertices.")
            .paramVec3("near", {0, 0, 0},
                       "Without strokes: the existing hole picked is the boundary loop with the "
                       "vertex nearest this point (ties: the lowest vertex).")
            .range(-1e9, 1e9)
            .node<CutRegionNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
