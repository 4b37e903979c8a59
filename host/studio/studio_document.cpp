#include "studio_document.hpp"

namespace geobrush::studio {

std::string StudioDocument::open(const std::filesystem::path& path) {
  Graph graph;
  std::set<std::string> missing;
  try {
    graph = readGraphFile(path);
    for (const auto& [name, node] : graph.nodes)
      if (!registry_.find(node.type)) missing.insert(name);
    // With a missing type the graph cannot be checked against its declarations: it is kept as
    // read, so that saving it loses nothing.
    if (missing.empty()) prepareGraph(graph, registry_, /*requireInputs=*/false);
  } catch (const GraphError& e) {
    return e.what();
  }
  graph_ = std::move(graph);
  path_ = path;
  missing_ = std::move(missing);
  return {};
}

std::string StudioDocument::save(const std::filesystem::path& path) {
  try {
    // Without the registry nothing is dropped: params are written as they are held.
    writeGraphFile(graph_, path);
  } catch (const std::exception& e) {
    return path.string() + ": " + e.what();
  }
  path_ = path;
  return {};
}

std::map<std::string, NodeStatus> StudioDocument::statuses(const EvalReport* report) const {
  std::map<std::string, NodeStatus> result;
  for (const auto& [name, node] : graph_.nodes) {
    NodeStatus& status = result[name];
    if (missing_.count(name)) {
      status.state = NodeState::Missing;
      status.message = "no loaded plugin provides '" + node.type + "'";
    }
  }
  if (!report) return result;
  for (const auto& run : report->runs) {
    NodeStatus& status = result[run.node];
    status.seconds = run.seconds;
    if (run.failed) {
      status.state = NodeState::Error;
      status.message = report->error;
    } else if (!run.warnings.empty()) {
      status.state = NodeState::Warning;
      for (const auto& warning : run.warnings) {
        if (!status.message.empty()) status.message += "\n";
        status.message += warning;
      }
    } else {
      status.state = NodeState::Ok;
    }
  }
  return result;
}

}  // namespace geobrush::studio
