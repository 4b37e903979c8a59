#include <memory>
#include <sstream>

#include "fill_holes.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

namespace {

using geobrush::Context;
using geobrush::Mesh;
using geobrush::NodeError;

// "all", "all-but-largest" or loop ids separated by commas.
geobrush::FillHolesOptions selection(const std::string& holes) {
  geobrush::FillHolesOptions options;
  if (holes == "all") return options;
  if (holes == "all-but-largest") {
    options.selection = geobrush::HoleSelection::AllButLargest;
    return options;
  }
  options.selection = geobrush::HoleSelection::Listed;
  const std::string wrong =
      "expected all, all-but-largest or loop ids like 0,2, not '" + holes + "'";
  if (holes.empty() || holes.back() == ',') throw NodeError::param("holes", wrong);
  std::stringstream list(holes);
  for (std::string item; std::getline(list, item, ',');) {
    if (item.empty() || item.size() > 9 ||
        item.find_first_not_of("0123456789") != std::string::npos)
      throw NodeError::param("holes", wrong);
    options.loops.push_back(std::stoi(item));
  }
  return options;
}

std::shared_ptr<geobrush::Metrics> report(const geobrush::FillHolesResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  auto& v = metrics->values;
  v["loops"] = double(result.holes.size());
  v["filled"] = v["new_vertices"] = v["new_faces"] = 0.0;
  for (const auto& hole : result.holes) {
    const std::string key = "loop." + std::to_string(hole.loop) + ".";
    v[key + "border_edges"] = hole.borderEdges;
    v[key + "border_mean_edge"] = hole.borderMeanEdge;
    v[key + "filled"] = hole.filled ? 1.0 : 0.0;
    if (!hole.filled) {
      metrics->notes.push_back("loop " + std::to_string(hole.loop) +
                               " left open: " + hole.leftOpen);
      continue;
    }
    v[key + "new_vertices"] = hole.newVertices;
    v[key + "new_faces"] = hole.newFaces;
    v[key + "new_mean_edge"] = hole.newMeanEdge;
    v[key + "continuity"] = hole.continuity;
    if (!hole.note.empty())
      metrics->notes.push_back("loop " + std::to_string(hole.loop) + " " + hole.note);
    v[key + "time_ms"] = hole.timeMs;
    v["filled"] += 1.0;
    v["new_vertices"] += hole.newVertices;
    v["new_faces"] += hole.newFaces;
  }
  return metrics;
}

// The fill as a paste: the input's vertices are the target's, the rest new; the seam faces are
// the new faces at the filled borders' vertices.
std::shared_ptr<geobrush::PasteMap> pasteMap(const geobrush::TriMesh& input,
                                             const geobrush::TriMesh& filled) {
  auto map = std::make_shared<geobrush::PasteMap>();
  map->targetVertex.assign(filled.n_vertices(), -1);
  map->sourceVertex.assign(filled.n_vertices(), -1);
  for (std::size_t v = 0; v < input.n_vertices(); ++v)
    map->targetVertex[v] = int(v);
  for (std::size_t f = input.n_faces(); f < filled.n_faces(); ++f)
    for (const auto v : filled.fv_range(geobrush::TriMesh::FaceHandle(int(f))))
      if (v.idx() < int(input.n_vertices())) {
        map->seamFaces.push_back(int(f));
        break;
      }
  return map;
}

class FillHolesNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto input = ctx.in<Mesh>("mesh");
    geobrush::FillHolesOptions options = selection(ctx.param<std::string>("holes"));
    options.maxBorderEdges = int(ctx.param<int>("max_border"));
    options.continuity = int(ctx.param<int>("continuity"));
    options.density = ctx.param<double>("density");
    geobrush::FillHolesResult result;
    try {
      result = geobrush::fillHoles(input->surface, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::param("holes", e.what());
    } catch (const geobrush::FillHolesError& e) {
      throw NodeError::input("mesh", e.what());
    }
    auto colors = input->vertexColors;
    if (!colors.empty()) colors.resize(result.mesh.n_vertices(), colors.back());
    ctx.out("mesh", std::make_shared<const Mesh>(result.mesh, std::move(colors)));
    ctx.out("map", pasteMap(input->surface, result.mesh));
    ctx.out("report", report(result));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.fill_holes", 1)
          .label("Fill Holes")
          .category("Mesh")
          .doc("Fills boundary loops with no placement to choose. Each loop gets its own chart "
               "(the loop's plane; for a loop that folds in every plane, its projection smoothed "
               "along the loop), a triangulation as dense as the mesh around the border, "
               "graded inward, and the membrane with G = 0 over it (harmonic, or biharmonic with "
               "the "
               "border's values and slopes). A border in a plane is capped flat. Existing "
               "vertices never move; the fill shares the border's vertices. A fill that would "
               "cut the surface is refilled harmonic, and fails naming its loop if it still "
               "would. Loops are numbered by their smallest vertex index.")
          .input<Mesh>("mesh", "The mesh with holes.")
          .output<Mesh>("mesh", "The input's vertices and faces in their order, then the fills'.")
          .output<geobrush::PasteMap>("map",
                                      "The fill as a paste, for geobrush.metrics and "
                                      "geobrush.fragment_complete: the input's vertices kept, "
                                      "the rest new, the new faces at the borders the seam.")
          .output<geobrush::Metrics>("report",
                                     "Per loop (loop.N.*): border_edges, border_mean_edge, "
                                     "filled, new_vertices, new_faces, new_mean_edge, continuity "
                                     "(the one the fill has: 0 where the border lies in a plane or "
                                     "its slopes fold the fill into the surface), time_ms; "
                                     "totals; a note for each loop left open.")
          .paramString("holes", "all",
                       "all, all-but-largest (leaves the longest loop open: a bust's base, a "
                       "sheet's edge) or loop ids separated by commas.")
          .paramInt("max_border", 0, "Loops with more border edges are left open; 0: no limit.")
          .range(0, 100000000)
          .paramInt("continuity", 1,
                    "0: harmonic (the border's values); 1: biharmonic (values and slopes).")
          .range(0, 1)
          .paramDouble("density", 1.4142135623730951,
                       "Liepa's density factor: larger gives smaller triangles than the border's.")
          .range(0.5, 8.0)
          .node<FillHolesNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
