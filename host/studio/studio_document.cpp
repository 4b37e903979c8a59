#include "studio_document.hpp"

#include <algorithm>
#include <optional>
#include <set>

namespace geobrush::studio {

void StudioDocument::newGraph() {
  graph_ = {};
  saved_ = {};
  path_.clear();
  missing_.clear();
  undo_.clear();
  redo_.clear();
  gestureStart_.reset();
}

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
  saved_ = graph_;
  path_ = path;
  missing_ = std::move(missing);
  undo_.clear();
  redo_.clear();
  gestureStart_.reset();
  return {};
}

// The graph as saved in another folder: relative input paths (meshes) rewritten to point at the
// same files from there. Output paths stay: they name files relative to where the graph runs.
Graph StudioDocument::rebased(const std::filesystem::path& path) const {
  Graph graph = graph_;
  const auto from = std::filesystem::absolute(graph_.baseDir()).lexically_normal();
  const auto to = std::filesystem::absolute(path).parent_path().lexically_normal();
  graph.file = path;
  if (from == to) return graph;
  for (auto& [name, node] : graph.nodes) {
    const NodeType* type = registry_.find(node.type);
    if (!type) continue;
    for (auto& [param, value] : node.params) {
      const ParamDecl* decl = type->findParam(param);
      if (!decl || decl->kind != ParamKind::InputPath ||
          !std::holds_alternative<std::string>(value))
        continue;
      const std::filesystem::path old = std::get<std::string>(value);
      if (old.empty() || old.is_absolute()) continue;
      const auto target = (from / old).lexically_normal();
      const auto relative = target.lexically_relative(to);
      value = (relative.empty() ? target : relative).generic_string();
    }
  }
  return graph;
}

std::string StudioDocument::save(const std::filesystem::path& path) {
  Graph graph = rebased(path);
  try {
    // Params are written as they are held, defaults too; lists in the rows their params declare.
    writeGraphFile(graph, path, &registry_, DefaultParams::Keep);
  } catch (const std::exception& e) {
    return path.string() + ": " + e.what();
  }
  // The document continues from the saved file: its paths resolve from there now.
  graph_ = std::move(graph);
  saved_ = graph_;
  path_ = path;
  return {};
}

bool StudioDocument::modified() const {
  const auto sameNode = [](const auto& a, const auto& b) {
    return a.first == b.first && a.second.type == b.second.type &&
           a.second.typeVersion == b.second.typeVersion && a.second.params == b.second.params;
  };
  return !(std::equal(graph_.nodes.begin(), graph_.nodes.end(), saved_.nodes.begin(),
                      saved_.nodes.end(), sameNode) &&
           graph_.connections == saved_.connections && graph_.ui == saved_.ui);
}

namespace {

std::string nodeText(const std::string& node) {
  return "node '" + node + "'";
}

}  // namespace

void StudioDocument::updateMissing() {
  missing_.clear();
  for (const auto& [name, node] : graph_.nodes)
    if (!registry_.find(node.type)) missing_.insert(name);
}

void StudioDocument::commit(Graph edited) {
  // Within a gesture the graph before it is already kept (once).
  if (gestureStart_)
    gestureChanged_ = true;
  else
    undo_.push_back(std::move(graph_));
  redo_.clear();
  graph_ = std::move(edited);
  updateMissing();
}

void StudioDocument::beginGesture() {
  endGesture();
  gestureStart_ = std::make_unique<Graph>(graph_);
  gestureChanged_ = false;
}

void StudioDocument::endGesture() {
  if (!gestureStart_) return;
  if (gestureChanged_) undo_.push_back(std::move(*gestureStart_));
  gestureStart_.reset();
  gestureChanged_ = false;
}

namespace {

// "what 'a'" or "what 'a' and n more".
std::string named(const std::string& what, const std::vector<std::string>& names) {
  std::string text = what + " " + names.front();
  if (names.size() > 1) text += " and " + std::to_string(names.size() - 1) + " more";
  return text;
}

std::string endpointText(const Endpoint& e) {
  return e.node + "." + e.port;
}

// A param's value in the graph file, or none where it keeps its default.
std::optional<ParamValue> valueIn(const ParamMap& params, const std::string& key) {
  const auto it = params.find(key);
  return it == params.end() ? std::nullopt : std::optional<ParamValue>(it->second);
}

std::vector<std::string> paramsChanged(const Graph& before, const Graph& after) {
  std::vector<std::string> changed;
  for (const auto& [name, node] : after.nodes) {
    const auto was = before.nodes.find(name);
    if (was == before.nodes.end()) continue;
    std::set<std::string> keys;
    for (const auto* params : {&node.params, &was->second.params})
      for (const auto& [key, value] : *params)
        keys.insert(key);
    for (const auto& key : keys)
      if (valueIn(node.params, key) != valueIn(was->second.params, key))
        changed.push_back(name + "." + key);
  }
  return changed;
}

}  // namespace

std::string describeEdit(const Graph& before, const Graph& after) {
  std::vector<std::string> added, removed;
  for (const auto& [name, node] : after.nodes)
    if (!before.nodes.count(name)) added.push_back(name);
  for (const auto& [name, node] : before.nodes)
    if (!after.nodes.count(name)) removed.push_back(name);
  if (!added.empty()) return named("add", added);
  if (!removed.empty()) return named("delete", removed);
  if (const auto changed = paramsChanged(before, after); !changed.empty())
    return named("set", changed);
  for (const Connection& c : after.connections)
    if (std::find(before.connections.begin(), before.connections.end(), c) ==
        before.connections.end())
      return "connect " + endpointText(c.from) + " to " + endpointText(c.to);
  for (const Connection& c : before.connections)
    if (std::find(after.connections.begin(), after.connections.end(), c) == after.connections.end())
      return "disconnect " + endpointText(c.from) + " from " + endpointText(c.to);
  std::vector<std::string> moved;
  for (const auto& [name, position] : after.ui) {
    const auto was = before.ui.find(name);
    if (was == before.ui.end() || !(was->second == position)) moved.push_back(name);
  }
  if (!moved.empty()) return named("move", moved);
  return "edit";
}

std::string StudioDocument::undoText() const {
  if (gestureStart_ && gestureChanged_) return describeEdit(*gestureStart_, graph_);
  return undo_.empty() ? std::string() : describeEdit(undo_.back(), graph_);
}

std::string StudioDocument::redoText() const {
  return redo_.empty() ? std::string() : describeEdit(graph_, redo_.back());
}

bool StudioDocument::undo() {
  endGesture();
  if (undo_.empty()) return false;
  redo_.push_back(std::move(graph_));
  graph_ = std::move(undo_.back());
  undo_.pop_back();
  updateMissing();
  return true;
}

bool StudioDocument::redo() {
  endGesture();
  if (redo_.empty()) return false;
  undo_.push_back(std::move(graph_));
  graph_ = std::move(redo_.back());
  redo_.pop_back();
  updateMissing();
  return true;
}

std::string StudioDocument::addNode(const std::string& typeId, double x, double y,
                                    std::string* name) {
  const NodeType* type = registry_.find(typeId);
  if (!type) return "no loaded plugin provides '" + typeId + "'";
  // "geobrush.load_mesh" -> "load_mesh", "load_mesh_2", ...
  const std::string stem = typeId.substr(typeId.rfind('.') + 1);
  std::string unique = stem;
  for (int k = 2; graph_.nodes.count(unique); ++k)
    unique = stem + "_" + std::to_string(k);
  Graph edited = graph_;
  edited.nodes[unique] = GraphNode{typeId, type->version, {}};
  edited.ui[unique] = {x, y};
  commit(std::move(edited));
  if (name) *name = unique;
  return {};
}

std::string StudioDocument::removeNodes(const std::vector<std::string>& names) {
  Graph edited = graph_;
  for (const auto& node : names) {
    if (!edited.nodes.erase(node)) return nodeText(node) + ": no such node";
    edited.ui.erase(node);
    std::erase_if(edited.connections,
                  [&](const Connection& c) { return c.from.node == node || c.to.node == node; });
  }
  commit(std::move(edited));
  return {};
}

std::string StudioDocument::connect(const Endpoint& from, const Endpoint& to) {
  const auto source = graph_.nodes.find(from.node), sink = graph_.nodes.find(to.node);
  if (source == graph_.nodes.end()) return nodeText(from.node) + ": no such node";
  if (sink == graph_.nodes.end()) return nodeText(to.node) + ": no such node";
  const NodeType* sourceType = registry_.find(source->second.type);
  const NodeType* sinkType = registry_.find(sink->second.type);
  const PortDecl* output = sourceType ? sourceType->findOutput(from.port) : nullptr;
  const PortDecl* input = sinkType ? sinkType->findInput(to.port) : nullptr;
  if (sourceType && !output) return nodeText(from.node) + " has no output '" + from.port + "'";
  if (sinkType && !input) return nodeText(to.node) + " has no input '" + to.port + "'";
  if (output && input && output->typeId != input->typeId) {
    return nodeText(to.node) + " input '" + to.port + "' takes " + input->typeId + ", not the " +
           output->typeId + " of " + nodeText(from.node) + " output '" + from.port + "'";
  }
  Graph edited = graph_;
  std::erase_if(edited.connections, [&](const Connection& c) { return c.to == to; });
  edited.connections.push_back({from, to});
  try {
    topologicalOrder(edited);
  } catch (const GraphError&) {
    return "connecting " + nodeText(from.node) + " to " + nodeText(to.node) + " makes a cycle";
  }
  commit(std::move(edited));
  return {};
}

std::string StudioDocument::setParam(const std::string& node, const std::string& param,
                                     ParamValue value) {
  const auto it = graph_.nodes.find(node);
  if (it == graph_.nodes.end()) return nodeText(node) + ": no such node";
  const NodeType* type = registry_.find(it->second.type);
  const ParamDecl* decl = type ? type->findParam(param) : nullptr;
  if (!decl) return nodeText(node) + " has no param '" + param + "'";
  try {
    value = coerceParam(*decl, value);
  } catch (const std::invalid_argument& e) {
    return nodeText(node) + " param '" + param + "': " + e.what();
  }
  if (const auto problem = checkParam(*decl, value))
    return nodeText(node) + " param '" + param + "': " + *problem;
  const auto current = it->second.params.find(param);
  if ((current != it->second.params.end() ? current->second : decl->defaultValue) == value)
    return {};
  Graph edited = graph_;
  edited.nodes[node].params[param] = std::move(value);
  commit(std::move(edited));
  return {};
}

std::optional<ParamValue> StudioDocument::param(const std::string& node,
                                                const std::string& param) const {
  const auto it = graph_.nodes.find(node);
  if (it == graph_.nodes.end()) return std::nullopt;
  if (const auto value = it->second.params.find(param); value != it->second.params.end())
    return value->second;
  const NodeType* type = registry_.find(it->second.type);
  const ParamDecl* decl = type ? type->findParam(param) : nullptr;
  if (!decl) return std::nullopt;
  return decl->defaultValue;
}

void StudioDocument::moveNode(const std::string& node, double x, double y) {
  const auto it = graph_.ui.find(node);
  if (it != graph_.ui.end() && it->second.x == x && it->second.y == y) return;
  Graph edited = graph_;
  edited.ui[node] = {x, y};
  commit(std::move(edited));
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
