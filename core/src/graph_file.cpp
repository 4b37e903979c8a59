// JSON form of graphs; the only file that sees nlohmann_json.
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "atomic_file.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/registry.hpp"

namespace geobrush {
namespace {

using nlohmann::json;

bool validNodeName(const std::string& name) {
  if (name.empty()) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

ParamValue paramFromJson(const json& value) {
  if (value.is_boolean()) return value.get<bool>();
  if (value.is_number_integer()) return value.get<std::int64_t>();
  if (value.is_number()) return value.get<double>();
  if (value.is_string()) return value.get<std::string>();
  if (value.is_array()) {
    // Numbers, or rows of numbers (e.g. dabs), flattened row by row.
    std::vector<double> list;
    for (const auto& item : value) {
      if (item.is_number()) {
        list.push_back(item.get<double>());
      } else if (item.is_array()) {
        for (const auto& x : item) {
          if (!x.is_number())
            throw std::invalid_argument("lists may hold only numbers or rows of numbers");
          list.push_back(x.get<double>());
        }
      } else {
        throw std::invalid_argument("lists may hold only numbers or rows of numbers");
      }
    }
    return list;
  }
  throw std::invalid_argument("unsupported value " + value.dump());
}

json paramToJson(const ParamValue& value, int rowSize) {
  struct Visitor {
    int rowSize;
    json operator()(bool b) const { return b; }
    json operator()(std::int64_t i) const { return i; }
    json operator()(double d) const { return d; }
    json operator()(const std::string& s) const { return s; }
    json operator()(const Vec3& v) const { return json::array({v[0], v[1], v[2]}); }
    json operator()(const std::vector<double>& list) const {
      json array = json::array();
      if (rowSize <= 1) {
        for (double d : list)
          array.push_back(d);
        return array;
      }
      for (std::size_t i = 0; i + rowSize <= list.size(); i += rowSize)
        array.push_back(json(std::vector<double>(list.begin() + i, list.begin() + i + rowSize)));
      return array;
    }
  };
  return std::visit(Visitor{rowSize}, value);
}

Endpoint parseEndpoint(const Graph& graph, const json& value, const char* key) {
  if (!value.is_string())
    throw GraphError(graph.file, "", "",
                     std::string("connection '") + key + "' must be \"node.port\"");
  const std::string text = value.get<std::string>();
  const auto dot = text.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size())
    throw GraphError(
        graph.file, "", "",
        std::string("connection '") + key + "' must be \"node.port\", got \"" + text + "\"");
  return {text.substr(0, dot), text.substr(dot + 1)};
}

template <typename T>
T require(const Graph& graph, const std::string& node, const json& object, const char* key,
          bool (json::*isType)() const noexcept, const char* what) {
  auto it = object.find(key);
  if (it == object.end())
    throw GraphError(graph.file, node, "", std::string("missing \"") + key + "\"");
  if (!((*it).*isType)())
    throw GraphError(graph.file, node, "", std::string("\"") + key + "\" must be " + what);
  return it->get<T>();
}

void rejectUnknownKeys(const Graph& graph, const std::string& node, const json& object,
                       std::initializer_list<const char*> known) {
  for (const auto& item : object.items()) {
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return item.key() == k; }))
      throw GraphError(graph.file, node, "", "unknown key \"" + item.key() + "\"");
  }
}

}  // namespace

Graph parseGraph(const std::string& text, const std::filesystem::path& file) {
  Graph graph;
  graph.file = file;
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    // e.what() carries "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    std::string what = e.what();
    auto at = what.find("parse error");
    throw GraphError(file, "", "",
                     "malformed JSON: " + (at == std::string::npos ? what : what.substr(at)));
  }
  if (!root.is_object()) throw GraphError(file, "", "", "a graph file must hold a JSON object");
  rejectUnknownKeys(graph, "", root, {"format", "formatVersion", "nodes", "connections", "ui"});
  if (root.value("format", json()) != kGraphFormat)
    throw GraphError(file, "", "", "not a GeoBrush graph (\"format\" must be \"geobrush-graph\")");
  const auto version = require<std::int64_t>(graph, "", root, "formatVersion",
                                             &json::is_number_integer, "an integer");
  if (version > kGraphFormatVersion)
    throw GraphError(file, "", "",
                     "formatVersion " + std::to_string(version) +
                         " was written by a newer GeoBrush; this one reads up to " +
                         std::to_string(kGraphFormatVersion));
  if (version < 1) throw GraphError(file, "", "", "formatVersion must be >= 1");

  const json nodes = root.value("nodes", json::object());
  if (!nodes.is_object())
    throw GraphError(file, "", "", "\"nodes\" must be an object keyed by node name");
  for (const auto& [name, entry] : nodes.items()) {
    if (!validNodeName(name))
      throw GraphError(file, name, "", "node names may use only letters, digits, '_' and '-'");
    if (!entry.is_object()) throw GraphError(file, name, "", "must be an object");
    rejectUnknownKeys(graph, name, entry, {"type", "typeVersion", "params"});
    GraphNode node;
    node.type = require<std::string>(graph, name, entry, "type", &json::is_string, "a string");
    node.typeVersion = int(require<std::int64_t>(graph, name, entry, "typeVersion",
                                                 &json::is_number_integer, "an integer"));
    const json params = entry.value("params", json::object());
    if (!params.is_object()) throw GraphError(file, name, "", "\"params\" must be an object");
    for (const auto& [param, value] : params.items()) {
      try {
        node.params[param] = paramFromJson(value);
      } catch (const std::exception& e) {
        throw GraphError(file, name, "param '" + param + "'", e.what());
      }
    }
    graph.nodes.emplace(name, std::move(node));
  }

  const json connections = root.value("connections", json::array());
  if (!connections.is_array()) throw GraphError(file, "", "", "\"connections\" must be an array");
  for (const auto& entry : connections) {
    if (!entry.is_object() || !entry.contains("from") || !entry.contains("to"))
      throw GraphError(file, "", "",
                       "each connection must be {\"from\": \"node.port\", \"to\": \"node.port\"}");
    graph.connections.push_back(
        {parseEndpoint(graph, entry["from"], "from"), parseEndpoint(graph, entry["to"], "to")});
  }

  const json ui = root.value("ui", json::object());
  if (!ui.is_object())
    throw GraphError(file, "", "", "\"ui\" must be an object keyed by node name");
  for (const auto& [name, entry] : ui.items()) {
    if (!entry.is_object()) throw GraphError(file, name, "", "ui entry must be an object");
    graph.ui[name] = {entry.value("x", 0.0), entry.value("y", 0.0)};
  }
  return graph;
}

Graph readGraphFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    throw GraphError(path, "", "",
                     std::filesystem::exists(path, ec) ? "cannot read the file" : "no such file");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parseGraph(text.str(), path);
}

std::string serializeGraph(const Graph& graph, const NodeRegistry* registry) {
  json root = json::object();
  root["format"] = kGraphFormat;
  root["formatVersion"] = kGraphFormatVersion;
  json nodes = json::object();
  for (const auto& [name, node] : graph.nodes) {
    const NodeType* type = registry ? registry->find(node.type) : nullptr;
    json params = json::object();
    for (const auto& [param, value] : node.params) {
      const ParamDecl* decl = type ? type->findParam(param) : nullptr;
      if (decl && decl->defaultValue == value) continue;
      params[param] = paramToJson(value, decl ? decl->rowSize : 1);
    }
    json entry = {{"type", node.type}, {"typeVersion", node.typeVersion}};
    if (!params.empty()) entry["params"] = params;
    nodes[name] = entry;
  }
  root["nodes"] = nodes;
  json connections = json::array();
  for (const auto& c : graph.connections)
    connections.push_back(
        {{"from", c.from.node + "." + c.from.port}, {"to", c.to.node + "." + c.to.port}});
  root["connections"] = connections;
  if (!graph.ui.empty()) {
    json ui = json::object();
    for (const auto& [name, pos] : graph.ui)
      ui[name] = {{"x", pos.x}, {"y", pos.y}};
    root["ui"] = ui;
  }
  return root.dump(2) + "\n";
}

void writeGraphFile(const Graph& graph, const std::filesystem::path& path,
                    const NodeRegistry* registry) {
  const std::string text = serializeGraph(graph, registry);
  try {
    writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out << text;
      if (!out.flush()) throw std::runtime_error("write failed");
    });
  } catch (const std::exception& e) {
    throw GraphError(path, "", "", std::string("cannot write the graph: ") + e.what());
  }
}

}  // namespace geobrush
