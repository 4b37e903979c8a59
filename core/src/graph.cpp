#include "geobrush/graph.hpp"

#include <algorithm>
#include <functional>
#include <set>

#include "geobrush/registry.hpp"
#include "geobrush/text.hpp"

namespace geobrush {
namespace {

std::string formatGraphError(const std::filesystem::path& file, const std::string& node,
                             const std::string& where, const std::string& cause) {
  // No file and no node: the cause names what it is about itself.
  if (file.empty() && node.empty() && where.empty()) return cause;
  std::string text = file.empty() ? std::string("<graph>") : escapeText(file.native(), 4096);
  if (!node.empty()) text += ": node " + quoteText(node);
  if (!where.empty()) text += (node.empty() ? ": " : " ") + where;
  return text + ": " + cause;
}

// "node.port", escaped (its names come from the file), for quoting in a message.
std::string describe(const Endpoint& endpoint) {
  return escapeText(endpoint.node + "." + endpoint.port);
}

std::string searchedDirsText(const NodeRegistry& registry) {
  std::string dirs;
  for (const auto& dir : registry.searchedDirs())
    dirs += (dirs.empty() ? "" : ", ") + escapeText(dir.native(), 4096);
  return dirs.empty() ? "no plugin folder searched" : "searched " + dirs;
}

void upgradeNode(const Graph& graph, const std::string& name, GraphNode& node,
                 const NodeType& type) {
  if (node.typeVersion > type.version) {
    throw GraphError(graph.file, name, "",
                     "saved with typeVersion " + std::to_string(node.typeVersion) + " of " +
                         quoteText(node.type) + ", newer than the loaded plugin's version " +
                         std::to_string(type.version) + " (" + type.library + ")");
  }
  if (node.typeVersion < 1) throw GraphError(graph.file, name, "", "typeVersion must be >= 1");
  for (; node.typeVersion < type.version; ++node.typeVersion) {
    auto it = type.upgrades.find(node.typeVersion);
    if (it == type.upgrades.end()) {
      throw GraphError(graph.file, name, "",
                       quoteText(node.type) + " has no upgrade from typeVersion " +
                           std::to_string(node.typeVersion) + " to " +
                           std::to_string(node.typeVersion + 1));
    }
    try {
      it->second(node.params);
    } catch (const std::exception& e) {
      throw GraphError(
          graph.file, name, "",
          "upgrade from typeVersion " + std::to_string(node.typeVersion) + " failed: " + e.what());
    }
  }
}

void coerceParams(const Graph& graph, const std::string& name, GraphNode& node,
                  const NodeType& type) {
  for (auto& [paramName, value] : node.params) {
    const ParamDecl* decl = type.findParam(paramName);
    if (!decl) {
      std::string known;
      for (const auto& p : type.params)
        known += (known.empty() ? "" : ", ") + p.name;
      throw GraphError(graph.file, name, "param " + quoteText(paramName),
                       quoteText(node.type) + " has no such parameter (it has: " +
                           (known.empty() ? "none" : known) + ")");
    }
    try {
      value = coerceParam(*decl, value);
    } catch (const std::exception& e) {
      throw GraphError(graph.file, name, "param " + quoteText(paramName), e.what());
    }
  }
}

void checkConnections(const Graph& graph, const NodeRegistry& registry, bool requireInputs) {
  std::set<std::pair<std::string, std::string>> fed;
  for (const auto& c : graph.connections) {
    const std::string where = "connection '" + describe(c.from) + " -> " + describe(c.to) + "'";
    auto from = graph.nodes.find(c.from.node);
    if (from == graph.nodes.end())
      throw GraphError(graph.file, c.from.node, where, "no node named " + quoteText(c.from.node));
    auto to = graph.nodes.find(c.to.node);
    if (to == graph.nodes.end())
      throw GraphError(graph.file, c.to.node, where, "no node named " + quoteText(c.to.node));
    const NodeType& fromType = *registry.find(from->second.type);
    const NodeType& toType = *registry.find(to->second.type);
    const PortDecl* out = fromType.findOutput(c.from.port);
    if (!out)
      throw GraphError(graph.file, c.from.node, "output " + quoteText(c.from.port),
                       "'" + fromType.id + "' has no such output (" + where + ")");
    const PortDecl* in = toType.findInput(c.to.port);
    if (!in)
      throw GraphError(graph.file, c.to.node, "input " + quoteText(c.to.port),
                       "'" + toType.id + "' has no such input (" + where + ")");
    if (out->typeId != in->typeId)
      throw GraphError(graph.file, c.to.node, "input " + quoteText(c.to.port),
                       "type mismatch: it takes " + in->typeId + " but '" + describe(c.from) +
                           "' gives " + out->typeId);
    if (!fed.insert({c.to.node, c.to.port}).second)
      throw GraphError(graph.file, c.to.node, "input " + quoteText(c.to.port),
                       "has more than one incoming connection");
  }
  for (const auto& [name, node] : graph.nodes) {
    if (!requireInputs) break;
    for (const auto& port : registry.find(node.type)->inputs) {
      if (!port.optional && !fed.count({name, port.name}))
        throw GraphError(graph.file, name, "input '" + port.name + "'",
                         "is not connected (it needs a " + port.typeId + ")");
    }
  }
}

}  // namespace

GraphError::GraphError(const std::filesystem::path& file, const std::string& node,
                       const std::string& where, const std::string& cause)
    : std::runtime_error(formatGraphError(file, node, where, cause)),
      file_(file),
      node_(node),
      where_(where),
      cause_(cause) {}

std::filesystem::path Graph::baseDir() const {
  if (file.empty()) return std::filesystem::current_path();
  return std::filesystem::absolute(file).parent_path();
}

const Connection* Graph::source(const std::string& node, const std::string& port) const {
  for (const auto& c : connections)
    if (c.to.node == node && c.to.port == port) return &c;
  return nullptr;
}

void prepareGraph(Graph& graph, const NodeRegistry& registry, bool requireInputs) {
  for (auto& [name, node] : graph.nodes) {
    const NodeType* type = registry.find(node.type);
    if (!type) {
      const std::string file = expectedPluginFile(node.type);
      if (auto reason = registry.refusal(file))
        throw GraphError(graph.file, name, "",
                         "node type " + quoteText(node.type) + " is unavailable: " + *reason);
      throw GraphError(graph.file, name, "",
                       "unknown node type " + quoteText(node.type) +
                           ": no loaded plugin provides it (expected plugin " +
                           escapeText(expectedPluginFile(node.type)) + "; " +
                           searchedDirsText(registry) + "; add folders with GEOBRUSH_PLUGIN_PATH)");
    }
    upgradeNode(graph, name, node, *type);
    coerceParams(graph, name, node, *type);
  }
  checkConnections(graph, registry, requireInputs);
  // A graph being edited may name one file twice for a while, as it may leave inputs open.
  if (requireInputs) checkOutputPaths(graph, registry);
  topologicalOrder(graph);
  std::erase_if(graph.ui, [&](const auto& entry) { return !graph.nodes.count(entry.first); });
}

void checkOutputPaths(const Graph& graph, const NodeRegistry& registry,
                      const std::filesystem::path& outputDir) {
  struct Writer {
    std::string node;
    std::string param;
  };
  std::map<std::filesystem::path, Writer> writers;
  for (const auto& [name, node] : graph.nodes) {
    const NodeType* type = registry.find(node.type);
    if (!type) continue;
    for (const auto& decl : type->params) {
      if (decl.kind != ParamKind::OutputPath) continue;
      const auto set = node.params.find(decl.name);
      const ParamValue& value = set == node.params.end() ? decl.defaultValue : set->second;
      const auto* text = std::get_if<std::string>(&value);
      if (!text || text->empty()) continue;  // an empty output path writes no file
      // As the evaluator resolves it; with no folder, a relative path stays relative.
      const std::filesystem::path path(*text);
      const auto file = (path.is_absolute() ? path : outputDir / path).lexically_normal();
      const auto [first, inserted] = writers.try_emplace(file, Writer{name, decl.name});
      if (!inserted)
        throw GraphError(graph.file, name, "param " + quoteText(decl.name),
                         "writes " + quotePath(file) + ", as node " +
                             quoteText(first->second.node) + " param " +
                             quoteText(first->second.param) +
                             " does: each would report writing it, and one would be lost");
    }
  }
}

void setParamFromText(Graph& graph, const NodeRegistry& registry, const std::string& assignment) {
  const auto equals = assignment.find('=');
  const auto dot = assignment.find('.');
  if (equals == std::string::npos || dot == std::string::npos || dot > equals)
    throw GraphError(graph.file, "", "",
                     "--set expects NODE.PARAM=VALUE, got " + quoteText(assignment));
  const std::string nodeName = assignment.substr(0, dot);
  const std::string paramName = assignment.substr(dot + 1, equals - dot - 1);
  auto it = graph.nodes.find(nodeName);
  if (it == graph.nodes.end())
    throw GraphError(graph.file, nodeName, "",
                     "no node of that name (in --set " + quoteText(assignment) + ")");
  const NodeType* type = registry.find(it->second.type);
  if (!type)
    throw GraphError(graph.file, nodeName, "", "unknown node type " + quoteText(it->second.type));
  const ParamDecl* decl = type->findParam(paramName);
  if (!decl)
    throw GraphError(graph.file, nodeName, "param " + quoteText(paramName),
                     "'" + type->id + "' has no such parameter");
  try {
    it->second.params[paramName] = parseParamText(*decl, assignment.substr(equals + 1));
  } catch (const std::exception& e) {
    throw GraphError(graph.file, nodeName, "param " + quoteText(paramName), e.what());
  }
}

std::vector<std::string> topologicalOrder(const Graph& graph) {
  std::map<std::string, int> pending;
  std::map<std::string, std::vector<std::string>> downstream;
  for (const auto& [name, node] : graph.nodes)
    pending[name] = 0;
  for (const auto& c : graph.connections) {
    if (!pending.count(c.from.node) || !pending.count(c.to.node)) continue;
    ++pending[c.to.node];
    downstream[c.from.node].push_back(c.to.node);
  }
  std::set<std::string> ready;
  for (const auto& [name, count] : pending)
    if (count == 0) ready.insert(name);
  std::vector<std::string> order;
  while (!ready.empty()) {
    std::string name = *ready.begin();
    ready.erase(ready.begin());
    order.push_back(name);
    for (const auto& next : downstream[name])
      if (--pending[next] == 0) ready.insert(next);
  }
  if (order.size() == graph.nodes.size()) return order;

  // Walk upstream inside the unfinished nodes until a node repeats: that is a cycle.
  std::string start;
  for (const auto& [name, count] : pending)
    if (count > 0) start = name;
  std::vector<std::string> path{start};
  std::set<std::string> onPath{start};
  while (true) {
    std::string upstream;
    for (const auto& c : graph.connections)
      if (c.to.node == path.back() && pending[c.from.node] > 0) upstream = c.from.node;
    if (onPath.count(upstream)) {
      const auto first = std::find(path.begin(), path.end(), upstream) - path.begin();
      std::string cycle = quoteText(upstream);
      for (auto k = std::ptrdiff_t(path.size()) - 1; k >= first; --k)
        cycle += " -> " + quoteText(path[k]);
      throw GraphError(graph.file, upstream, "", "the graph has a cycle: " + cycle);
    }
    path.push_back(upstream);
    onPath.insert(upstream);
  }
}

}  // namespace geobrush
