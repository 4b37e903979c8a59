// `geobrush fill`: a mesh's holes filled by the fill_holes node, in a graph made from arguments.
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "geobrush/text.hpp"

namespace geobrush::cli {
namespace {

namespace fs = std::filesystem;

Graph fillGraph(const FillOptions& options) {
  const auto absolute = [](const fs::path& path) {
    return fs::absolute(path).lexically_normal().string();
  };
  Graph graph;
  graph.file = options.mesh;  // what messages name
  graph.nodes["mesh"] = {"geobrush.load_mesh", 1, {{"path", absolute(options.mesh)}}};
  graph.nodes["fill"] = {"geobrush.fill_holes",
                         1,
                         {{"holes", options.holes},
                          {"max_border", std::int64_t(options.maxBorder)},
                          {"continuity", std::int64_t(options.continuity)}}};
  graph.nodes["save"] = {"geobrush.save_mesh", 1, {{"path", absolute(options.output)}}};
  graph.connections.push_back({{"mesh", "mesh"}, {"fill", "mesh"}});
  graph.connections.push_back({{"fill", "mesh"}, {"save", "mesh"}});
  if (!options.image.empty()) {
    graph.nodes["picture"] = {"geobrush.render", 1, {{"path", absolute(options.image)}}};
    graph.connections.push_back({{"fill", "mesh"}, {"picture", "mesh"}});
  }
  return graph;
}

// One line per loop: what the fill added, or why the loop is left open.
void printHoles(const std::map<std::string, double>& metrics,
                const std::vector<std::string>& notes) {
  const auto value = [&](const std::string& key) {
    const auto it = metrics.find("fill.loop." + key);
    return it == metrics.end() ? 0.0 : it->second;
  };
  const int loops = int(metrics.count("fill.loops") ? metrics.at("fill.loops") : 0);
  for (int i = 0; i < loops; ++i) {
    const std::string id = std::to_string(i) + ".";
    if (value(id + "filled") == 0.0) continue;
    std::fprintf(stderr, "loop %d: %d border edges, filled with %d new vertices in %.1f ms\n", i,
                 int(value(id + "border_edges")), int(value(id + "new_vertices")),
                 value(id + "time_ms"));
  }
  for (const auto& note : notes)
    std::fprintf(stderr, "%s\n", messageLine(note).c_str());
}

}  // namespace

bool isHoleChoice(const std::string& holes) {
  if (holes == "all" || holes == "all-but-largest") return true;
  if (holes.empty() || holes.front() == ',' || holes.back() == ',' ||
      holes.find(",,") != std::string::npos)
    return false;
  return holes.find_first_not_of("0123456789,") == std::string::npos;
}

int fillHoles(const FillOptions& options) {
  if (!isHoleChoice(options.holes)) {
    printError("fill: --holes: expected all, all-but-largest or loop ids like 0,2, not " +
               quoteText(options.holes));
    return kExitUsage;
  }
  NodeRegistry registry;
  const auto pluginErrors = loadPlugins(registry, options.quiet || options.json);
  Graph graph = fillGraph(options);
  try {
    prepareGraph(graph, registry);
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitUsage;
  }
  Evaluator evaluator(registry);
  const EvalReport report = evaluateAndReport(
      graph, registry, {},
      {options.mesh, false, options.quiet || options.json, false, options.progress}, pluginErrors,
      &evaluator);
  CollectedMetrics metrics;
  if (report.ok) metrics = collectMetrics(graph, registry, evaluator);
  if (options.json)
    std::cout << fillReportJson(options.mesh, report, pluginErrors, metrics.values, metrics.notes);
  else if (report.ok && !options.quiet)
    printHoles(metrics.values, metrics.notes);
  return report.ok ? kExitOk : kExitEvaluation;
}

}  // namespace geobrush::cli
