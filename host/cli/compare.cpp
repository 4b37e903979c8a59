// `geobrush compare`: two graphs (e.g. the same clone with two blending stages) evaluated side by
// side, their metrics and node times in one table, their measured meshes in one picture.
#include <Eigen/Geometry>
#include <cstdio>
#include <iostream>
#include <optional>
#include <set>

#include "commands.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/region.hpp"
#include "geobrush/text.hpp"
#include "geobrush/values.hpp"

namespace geobrush::cli {
namespace {

constexpr std::string_view kMetricsNode = "geobrush.metrics";

// The direction in which a measure of the geobrush.metrics node (or a node's time) is better:
// -1 lower, +1 higher, 0 unknown. Keyed by the name after the node's.
int betterDirection(const std::string& key) {
  static const std::map<std::string, int, std::less<>> kDirections = {
      {"manifold", +1},
      {"non_manifold_vertices", -1},
      {"seam_unshared_vertices", -1},
      {"seam_normal_jump_mean_deg", -1},
      {"seam_normal_jump_p95_deg", -1},
      {"detail_difference_percent", -1},
      {"new_self_intersections", -1}};
  // A node's time varies from run to run by more than most differences between two graphs;
  // the total says which is faster.
  if (key == "time_ms.total") return -1;
  const auto dot = key.rfind('.');
  const auto it = kDirections.find(dot == std::string::npos ? key : key.substr(dot + 1));
  return it == kDirections.end() ? 0 : it->second;
}

// The folder of one side's file outputs: the graph's name, told apart when both are the same.
std::filesystem::path sideFolder(const std::filesystem::path& out,
                                 const std::filesystem::path& graph, const char* side,
                                 bool sameNames) {
  std::string name = graph.stem().string();
  if (sameNames) {
    name += "_";
    name += side;
  }
  return out / name;
}

// The mesh input of the graph's first metrics node (in name order): what the picture shows.
const Connection* measuredMesh(const Graph& graph) {
  for (const auto& [name, node] : graph.nodes)
    if (node.type == kMetricsNode)
      if (const Connection* c = graph.source(name, "mesh")) return c;
  return nullptr;
}

// Reads and checks one side's graph, to run with its outputs in `outDir`; false, with the error on
// the side, when it cannot be used.
bool prepareSide(const NodeRegistry& registry, ComparedGraph& side, Graph& graph,
                 const std::vector<std::string>& sets, const std::filesystem::path& outDir) {
  try {
    graph = readGraphFile(side.graph);
    prepareGraph(graph, registry);
    for (const auto& assignment : sets)
      setParamFromText(graph, registry, assignment);
    checkOutputPaths(graph, registry, std::filesystem::absolute(outDir));
  } catch (const GraphError& e) {
    side.report.ok = false;
    side.report.error = e.what();
    return false;
  }
  if (!measuredMesh(graph)) {
    side.report.ok = false;
    side.report.error = escapeText(side.graph.native(), 4096) +
                        ": no geobrush.metrics node measures a mesh: " +
                        "compare reads its metrics and pictures the mesh it measures";
    return false;
  }
  return true;
}

bool evaluateSide(const NodeRegistry& registry, ComparedGraph& side, const Graph& graph,
                  const std::filesystem::path& outDir, const CompareOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (ec) {
    side.report.ok = false;
    side.report.error = quotePath(outDir) + ": cannot create the output folder: " + ec.message();
    return false;
  }
  EvalOptions eval;
  eval.outputDir = outDir;
  Evaluator evaluator(registry);
  // Reported here: its errors go to the comparison's own report.
  side.report = evaluateWithProgress(evaluator, graph, eval,
                                     {side.graph, false, options.quiet, false, options.progress});
  if (!side.report.ok) return false;
  CollectedMetrics collected = collectMetrics(graph, registry, evaluator);
  side.metrics = std::move(collected.values);
  side.notes = std::move(collected.notes);
  const Connection* measured = measuredMesh(graph);
  side.mesh = std::dynamic_pointer_cast<const Mesh>(
      evaluator.output(measured->from.node, measured->from.port));
  if (const Connection* map = graph.source(measured->to.node, "map"))
    side.map =
        std::dynamic_pointer_cast<const PasteMap>(evaluator.output(map->from.node, map->from.port));
  return side.mesh != nullptr;
}

std::string cell(const std::map<std::string, double>& values, const std::string& key) {
  const auto it = values.find(key);
  if (it == values.end()) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", it->second);
  return text;
}

void printRow(const std::string& key, const std::map<std::string, double>& a,
              const std::map<std::string, double>& b, int width) {
  std::printf("%-48s %*s %*s %6s\n", key.c_str(), width, cell(a, key).c_str(), width,
              cell(b, key).c_str(), betterSide(key, a, b).c_str());
}

void printTable(const ComparedGraph& a, const ComparedGraph& b) {
  std::set<std::string> keys;
  for (const auto* side : {&a, &b})
    for (const auto& [key, value] : side->metrics)
      keys.insert(key);
  std::map<std::string, double> timesA, timesB;
  for (const auto& [side, times] : {std::pair{&a, &timesA}, std::pair{&b, &timesB}}) {
    for (const auto& run : side->report.runs) {
      (*times)["time_ms." + run.node] = 1e3 * run.seconds;
      (*times)["time_ms.total"] += 1e3 * run.seconds;
    }
  }
  std::set<std::string> timeKeys;
  for (const auto* times : {&timesA, &timesB})
    for (const auto& [key, value] : *times)
      timeKeys.insert(key);
  const std::string nameA = "a: " + a.graph.filename().string();
  const std::string nameB = "b: " + b.graph.filename().string();
  const int width = int(std::max({std::size_t(18), nameA.size(), nameB.size()}));
  std::printf("%-48s %*s %*s %6s\n", "", width, nameA.c_str(), width, nameB.c_str(), "better");
  for (const auto& key : keys)
    printRow(key, a.metrics, b.metrics, width);
  for (const auto& key : timeKeys)
    printRow(key, timesA, timesB, width);
  for (const auto* side : {&a, &b})
    for (const auto& note : side->notes)
      std::printf("note: %s: %s\n", side->graph.filename().c_str(), note.c_str());
}

// The view that frames a side's paste: the pasted and seam vertices of its map, seen from outside
// the mesh there; nothing (the whole mesh) without a map.
std::optional<CloneView> pasteView(const ComparedGraph& side) {
  if (!side.map) return std::nullopt;
  const TriMesh& mesh = side.mesh->surface;
  std::vector<char> pasted(mesh.n_vertices(), 0);
  for (std::size_t v = 0; v < side.map->sourceVertex.size() && v < pasted.size(); ++v)
    pasted[v] = side.map->sourceVertex[v] >= 0;
  for (int f : side.map->seamFaces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      pasted[std::size_t(v.idx())] = 1;
  Eigen::AlignedBox3d box;
  for (auto v : mesh.vertices())
    if (pasted[std::size_t(v.idx())]) box.extend(Eigen::Vector3d(mesh.point(v).data()));
  if (box.isEmpty()) return std::nullopt;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge_handle(f);
    const auto a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h),
               c = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
    if (!pasted[std::size_t(a.idx())] && !pasted[std::size_t(b.idx())] &&
        !pasted[std::size_t(c.idx())])
      continue;
    const auto n = (mesh.point(b) - mesh.point(a)) % (mesh.point(c) - mesh.point(a));
    normal += Eigen::Vector3d(n.data());  // area-weighted
  }
  const Eigen::Vector3d centre = box.center();
  return viewFacing({centre.x(), centre.y(), centre.z()}, 0.5 * box.diagonal().norm(),
                    {normal.x(), normal.y(), normal.z()});
}

// Both meshes, left and right, each framed on its paste and labelled with its graph's name.
Image sideBySide(const ComparedGraph& a, const ComparedGraph& b, const RenderOptions& options) {
  Image images[2];
  int k = 0;
  for (const auto* side : {&a, &b}) {
    RenderItem item;
    item.mesh = side->mesh;
    RenderOptions framed = options;
    if (const auto view = pasteView(*side)) {
      framed.frame = RenderFrame{view->focus, view->radius};
      framed.view.azimuthDeg = view->azimuthDeg;
      framed.view.elevationDeg = view->elevationDeg;
    }
    images[k] = renderMeshes({item}, framed).image;
    drawLabel(images[k], std::string(k == 0 ? "a: " : "b: ") + side->graph.stem().string());
    ++k;
  }
  Image both(images[0].width + images[1].width, std::max(images[0].height, images[1].height));
  for (int i = 0; i < 2; ++i)
    for (int y = 0; y < images[i].height; ++y)
      for (int x = 0; x < images[i].width; ++x)
        std::copy_n(images[i].pixel(x, y), 4, both.pixel(x + i * images[0].width, y));
  return both;
}

}  // namespace

std::string betterSide(const std::string& key, const std::map<std::string, double>& a,
                       const std::map<std::string, double>& b) {
  const int direction = betterDirection(key);
  const auto x = a.find(key), y = b.find(key);
  if (direction == 0 || x == a.end() || y == b.end()) return "";
  if (x->second == y->second) return "=";
  return (x->second < y->second) == (direction < 0) ? "a" : "b";
}

int compareGraphs(const CompareOptions& options) {
  NodeRegistry registry;
  const auto pluginErrors = registry.loadPlugins(defaultPluginDirs()).errors;
  if (!options.quiet && !options.json)
    for (const auto& error : pluginErrors)
      printWarning(error);
  ComparedGraph a, b;
  a.graph = options.graphA;
  b.graph = options.graphB;
  const bool sameNames = options.graphA.stem() == options.graphB.stem();
  Graph graphA, graphB;
  const std::filesystem::path image =
      options.image.empty() ? options.outDir / "compare.png" : options.image;
  const auto folderA = sideFolder(options.outDir, a.graph, "a", sameNames);
  const auto folderB = sideFolder(options.outDir, b.graph, "b", sameNames);
  int status = kExitOk;
  std::string error;
  // Both graphs are read and checked before either runs.
  if (!prepareSide(registry, a, graphA, options.sets, folderA)) {
    error = a.report.error;
    status = kExitUsage;
  } else if (!prepareSide(registry, b, graphB, options.sets, folderB)) {
    error = b.report.error;
    status = kExitUsage;
  } else if (!evaluateSide(registry, a, graphA, folderA, options)) {
    error = a.report.error;
    status = kExitEvaluation;
  } else if (!evaluateSide(registry, b, graphB, folderB, options)) {
    error = b.report.error;
    status = kExitEvaluation;
  } else {
    try {
      writePng(sideBySide(a, b, options.render), image);
    } catch (const std::exception& e) {
      error = image.string() + ": " + e.what();
      status = kExitEvaluation;
    }
  }
  if (!error.empty()) printError(error);
  if (options.json) {
    std::cout << compareReportJson(a, b, status == kExitOk ? image : std::filesystem::path(),
                                   error);
  } else if (status == kExitOk) {
    if (!options.quiet) printTable(a, b);
    if (!options.quiet) std::fprintf(stderr, "wrote %s\n", messageLine(image.native()).c_str());
  }
  return status;
}

}  // namespace geobrush::cli
