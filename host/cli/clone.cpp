// `geobrush clone`: a method template filled from plain arguments, then evaluated.
#include <cstdio>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "geobrush/text.hpp"
#include "geobrush/values.hpp"

namespace geobrush::cli {
namespace {

namespace fs = std::filesystem;

// SOURCE_on_TARGET.obj in the working folder.
fs::path defaultOutput(const CloneSpec& spec) {
  return spec.source.stem().string() + "_on_" + spec.target.stem().string() + ".obj";
}

// The meshes the method loads, through the evaluator that then runs the clone (so they are read
// once): snapping needs them before the other params can be set.
std::pair<MeshPtr, MeshPtr> loadMeshes(Evaluator& evaluator, const NodeRegistry& registry,
                                       const Graph& graph, const CloneOptions& options) {
  EvalOptions loads;
  loads.targets = {"source_mesh", "target_mesh"};
  const EvalReport report = evaluateAndReport(
      graph, registry, loads, {"clone " + options.method, false, true}, {}, &evaluator);
  if (!report.ok) return {};
  return {std::dynamic_pointer_cast<const Mesh>(evaluator.output("source_mesh", "mesh")),
          std::dynamic_pointer_cast<const Mesh>(evaluator.output("target_mesh", "mesh"))};
}

// Snaps the points, saying how far a point had to move.
SnappedSpec snapped(const CloneSpec& spec, const Mesh& source, const Mesh& target, bool quiet) {
  const SnappedSpec result = snapToSurfaces(spec, source.surface, target.surface);
  const auto note = [&](const char* which, double moved, const Vec3& point) {
    // Points typed with a few decimals land a trace off the surface; say so only when the move
    // is a visible part of the region.
    if (quiet || moved <= 0.01 * spec.radius) return;
    std::fprintf(stderr, "note: the %s point moved %s onto the surface, to %s\n", which,
                 formatParam(moved).c_str(), formatParam(point).c_str());
  };
  note("source", result.sourceMoved, result.spec.sourcePoint);
  note("target", result.targetMoved, result.spec.targetPoint);
  return result;
}

// The meshes are arguments: a missing one is a usage error, as a missing graph file is.
std::optional<std::string> missingMesh(const CloneOptions& options) {
  for (const auto& [option, path] :
       {std::pair{"--source", options.spec.source}, std::pair{"--target", options.spec.target}}) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      return std::string(option) + ": " + quotePath(path) +
             (fs::exists(path, ec) ? ": not a regular file" : ": no such file");
  }
  return std::nullopt;
}

}  // namespace

int cloneMeshes(const CloneOptions& options) {
  NodeRegistry registry;
  const auto pluginErrors = loadPlugins(registry, options.quiet || options.json);
  const CloneOutputs outputs{options.output.empty() ? defaultOutput(options.spec) : options.output,
                             options.image};
  if (const auto missing = missingMesh(options)) {
    printError(*missing);
    return kExitUsage;
  }
  Graph graph;
  try {
    graph = readMethod(options.method, defaultMethodDirs(), registry);
    fillCloneGraph(graph, registry, options.spec, outputs);
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitUsage;
  }

  Evaluator evaluator(registry);
  const auto [source, target] = loadMeshes(evaluator, registry, graph, options);
  if (!source || !target) return kExitEvaluation;
  try {
    const SnappedSpec onSurfaces = snapped(options.spec, *source, *target, options.quiet);
    fillCloneGraph(graph, registry, onSurfaces.spec, outputs, cloneView(onSurfaces));
    for (const auto& assignment : options.sets)
      setParamFromText(graph, registry, assignment);
    checkOutputPaths(graph, registry, fs::current_path());
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitUsage;
  }

  const EvalReport report = evaluateAndReport(
      graph, registry, {}, {"clone " + options.method, options.json, options.quiet, true},
      pluginErrors, &evaluator);
  if (!report.ok) return kExitEvaluation;
  // Written last: a failed clone leaves nothing behind.
  if (options.saveGraph.empty()) return kExitOk;
  try {
    writeGraphFile(graph, options.saveGraph, &registry);
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitEvaluation;
  }
  if (!options.quiet && !options.json)
    std::fprintf(stderr, "wrote %s\n", messageLine(options.saveGraph.native()).c_str());
  return kExitOk;
}

int listMethods() {
  for (const auto& method : findMethods(defaultMethodDirs()))
    std::printf("%s  %s\n", method.name.c_str(), messageLine(method.file.native()).c_str());
  return kExitOk;
}

}  // namespace geobrush::cli
