// `geobrush compare`: two graphs (e.g. the same clone with two blending stages) evaluated side by
// side, their metrics and node times in one table, their measured meshes in one picture.
#include <cstdio>
#include <iostream>
#include <set>

#include "commands.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/text.hpp"
#include "geobrush/values.hpp"

namespace geobrush::cli {
namespace {

constexpr std::string_view kMetricsNode = "geobrush.metrics";

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
                  const std::filesystem::path& outDir) {
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
  side.report = evaluator.evaluate(graph, eval);
  if (!side.report.ok) return false;
  CollectedMetrics collected = collectMetrics(graph, registry, evaluator);
  side.metrics = std::move(collected.values);
  side.notes = std::move(collected.notes);
  const Connection* measured = measuredMesh(graph);
  side.mesh = std::dynamic_pointer_cast<const Mesh>(
      evaluator.output(measured->from.node, measured->from.port));
  return side.mesh != nullptr;
}

std::string cell(const std::map<std::string, double>& values, const std::string& key) {
  const auto it = values.find(key);
  if (it == values.end()) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", it->second);
  return text;
}

void printTable(const ComparedGraph& a, const ComparedGraph& b) {
  std::set<std::string> keys;
  for (const auto* side : {&a, &b})
    for (const auto& [key, value] : side->metrics)
      keys.insert(key);
  std::map<std::string, double> timesA, timesB;
  for (const auto& run : a.report.runs)
    timesA["time_ms." + run.node] = 1e3 * run.seconds;
  for (const auto& run : b.report.runs)
    timesB["time_ms." + run.node] = 1e3 * run.seconds;
  std::set<std::string> timeKeys;
  for (const auto* times : {&timesA, &timesB})
    for (const auto& [key, value] : *times)
      timeKeys.insert(key);
  std::printf("%-48s %18s %18s\n", "", a.graph.filename().c_str(), b.graph.filename().c_str());
  for (const auto& key : keys)
    std::printf("%-48s %18s %18s\n", key.c_str(), cell(a.metrics, key).c_str(),
                cell(b.metrics, key).c_str());
  for (const auto& key : timeKeys)
    std::printf("%-48s %18s %18s\n", key.c_str(), cell(timesA, key).c_str(),
                cell(timesB, key).c_str());
  for (const auto* side : {&a, &b})
    for (const auto& note : side->notes)
      std::printf("note: %s: %s\n", side->graph.filename().c_str(), note.c_str());
}

// Both meshes rendered with the same settings, left and right.
Image sideBySide(const ComparedGraph& a, const ComparedGraph& b, const RenderOptions& options) {
  Image images[2];
  int k = 0;
  for (const auto* side : {&a, &b}) {
    RenderItem item;
    item.mesh = side->mesh;
    images[k++] = renderMeshes({item}, options).image;
  }
  Image both(images[0].width + images[1].width, std::max(images[0].height, images[1].height));
  for (int i = 0; i < 2; ++i)
    for (int y = 0; y < images[i].height; ++y)
      for (int x = 0; x < images[i].width; ++x)
        std::copy_n(images[i].pixel(x, y), 4, both.pixel(x + i * images[0].width, y));
  return both;
}

}  // namespace

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
  } else if (!evaluateSide(registry, a, graphA, folderA)) {
    error = a.report.error;
    status = kExitEvaluation;
  } else if (!evaluateSide(registry, b, graphB, folderB)) {
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
