// A node type wired for a test on its own: every required input fed by nodes of other types
// that run with their defaults (no files), as the conformance suites use it.
#pragma once

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>
#include <vector>

#include "geobrush/graph.hpp"
#include "geobrush/registry.hpp"
#include "test_support.hpp"

namespace geobrush::test {

// Adds nodes that produce a value of `typeId` and returns the output feeding
// it: the first type (by id) whose required inputs can be fed in turn. The meshes they start from
// have `resolution` segments a side.
inline std::optional<Endpoint> feed(Graph& graph, const std::string& typeId, int depth,
                                    int resolution = 16) {
  if (depth > 4) return std::nullopt;
  // Producers with the fewest inputs first, so that feeding stays shallow.
  auto producers = registry().types();
  const auto requiredInputs = [](const NodeType* type) {
    return std::count_if(type->inputs.begin(), type->inputs.end(),
                         [](const PortDecl& port) { return !port.optional; });
  };
  std::stable_sort(producers.begin(), producers.end(), [&](const NodeType* a, const NodeType* b) {
    return requiredInputs(a) < requiredInputs(b);
  });
  for (const NodeType* type : producers) {
    const PortDecl* out = nullptr;
    for (const auto& port : type->outputs)
      if (port.typeId == typeId) out = &port;
    // A feeder reads and writes no files.
    const bool usesFiles = std::any_of(type->params.begin(), type->params.end(), [](auto& p) {
      return p.kind == ParamKind::InputPath || p.kind == ParamKind::OutputPath;
    });
    if (!out || usesFiles) continue;
    Graph trial = graph;
    const std::string name = "feed" + std::to_string(trial.nodes.size());
    trial.nodes[name] = {type->id, type->version, {}};
    // A small relief plane (the suites evaluate every node type many times; the primitive's
    // default sphere has 40,962 vertices), whose boundary the hole-filling types take for a hole
    // and on which the maps' default origin (0, 0, 0) lies.
    if (type->id == "geobrush.primitive")
      trial.nodes[name].params = {{"shape", std::string("plane")},
                                  {"size", 2.0},
                                  {"resolution", std::int64_t(resolution)},
                                  {"relief", 0.02}};
    // Something painted, so that what is fed is a clone's: a source canvas around the plane's
    // centre and a region around the domain's origin (the defaults paint nothing and fail).
    if (type->id == "geobrush.canvas_grow")
      trial.nodes[name].params["dabs"] = std::vector<double>{0, 0, 0, 0.6};
    if (type->id == "geobrush.strokes")
      trial.nodes[name].params["dabs"] = std::vector<double>{0, 0, 0.15, 1};
    bool ok = true;
    for (const auto& in : type->inputs) {
      if (in.optional) continue;
      auto source = feed(trial, in.typeId, depth + 1, resolution);
      if (!source) {
        ok = false;
        break;
      }
      trial.connections.push_back({*source, {name, in.name}});
    }
    if (!ok) continue;
    graph = std::move(trial);
    return Endpoint{name, out->name};
  }
  return std::nullopt;
}

// A graph of the node under test ("subject") with every required input fed; none where no node
// type produces one of them. `suite` names the temporary folder its files go to. With
// `mixedMeshes`, each input comes from a mesh of another resolution (16, 13, 10, ... segments),
// as a graph wired across two clones would give them.
inline std::optional<Graph> wiredNode(const NodeType& type, const std::string& suite,
                                      bool mixedMeshes = false) {
  Graph graph;
  graph.file = tempDir(suite + "-" + type.id) / "graph.json";
  graph.nodes["subject"] = {type.id, type.version, {}};
  int resolution = 16;
  for (const auto& in : type.inputs) {
    if (in.optional) continue;
    auto source = feed(graph, in.typeId, 0, resolution);
    if (mixedMeshes) resolution = std::max(4, resolution - 3);
    if (!source) return std::nullopt;
    graph.connections.push_back({*source, {"subject", in.name}});
  }
  return graph;
}

// Every node type the build's plugins register, by id.
inline std::vector<std::string> allNodeTypeIds() {
  std::vector<std::string> ids;
  for (const NodeType* type : registry().types())
    ids.push_back(type->id);
  return ids;
}

// A test name made of a type id ("geobrush.stitch" -> "geobrush_stitch").
inline std::string typeTestName(std::string id) {
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return id;
}

}  // namespace geobrush::test
