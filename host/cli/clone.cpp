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

// The meshes the method loads, through the evaluator that then runs the clone (so they are read
// once): snapping needs them before the other params can be set.
std::pair<MeshPtr, MeshPtr> loadMeshes(Evaluator& evaluator, const NodeRegistry& registry,
                                       const Graph& graph, const CloneOptions& options) {
  EvalOptions loads;
  loads.targets.assign(std::begin(kCloneMeshNodes), std::end(kCloneMeshNodes));
  const EvalReport report = evaluateAndReport(
      graph, registry, loads,
      {"clone " + options.request.method, false, true, false, options.progress}, {}, &evaluator);
  if (!report.ok) return {};
  return {std::dynamic_pointer_cast<const Mesh>(evaluator.output("source_mesh", "mesh")),
          std::dynamic_pointer_cast<const Mesh>(evaluator.output("target_mesh", "mesh"))};
}

// Says how far a point had to move onto its surface.
void noteSnaps(const SnappedSpec& snapped, double radius) {
  const auto note = [&](const char* which, double moved, const Vec3& point) {
    // Points typed with a few decimals land a trace off the surface; say so only when the move
    // is a visible part of the region.
    if (moved <= 0.01 * radius) return;
    std::fprintf(stderr, "note: the %s point moved %s onto the surface, to %s\n", which,
                 formatParam(moved).c_str(), formatParam(point).c_str());
  };
  note("source", snapped.sourceMoved, snapped.spec.sourcePoint);
  note("target", snapped.targetMoved, snapped.spec.targetPoint);
}

}  // namespace

int cloneMeshes(const CloneOptions& options) {
  NodeRegistry registry;
  const auto pluginErrors = loadPlugins(registry, options.quiet || options.json);
  CloneRequest request = options.request;
  if (request.outputs.mesh.empty()) request.outputs.mesh = defaultCloneOutput(request.spec);
  Graph graph;
  try {
    graph = startCloneGraph(request, registry);
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitUsage;
  }

  Evaluator evaluator(registry);
  const auto [source, target] = loadMeshes(evaluator, registry, graph, options);
  if (!source || !target) return kExitEvaluation;
  try {
    const SnappedSpec snapped = finishCloneGraph(graph, request, registry, *source, *target);
    if (!options.quiet) noteSnaps(snapped, request.spec.radius);
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitUsage;
  }

  const EvalReport report = evaluateAndReport(
      graph, registry, {},
      {"clone " + request.method, options.json, options.quiet, true, options.progress},
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
