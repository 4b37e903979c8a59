// JSON form of graphs; the only file that sees nlohmann_json.
#include <algorithm>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "atomic_file.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/text.hpp"

namespace geobrush {
namespace {

// Objects keep the order of their keys: a file read keeps its order when written back.
using json = nlohmann::ordered_json;

// Graph files are kilobytes; a larger file is a wrong path (a device, a mesh, a log), and reading
// it whole would cost its size in memory.
constexpr std::size_t kMaxGraphFileBytes = std::size_t(64) << 20;
// A graph file nests six levels (root, nodes, node, params, dab rows, numbers).
constexpr std::size_t kMaxJsonDepth = 64;

// A JSON key as messages show it: "key".
std::string jsonKey(std::string_view key) {
  std::string text = "\"";
  text += escapeText(key);
  text += '"';
  return text;
}

// Where in a graph file something is, as GraphError names it.
struct Place {
  std::string node;
  std::string where;
};

// The node and param (or key) that a path of keys from the root names: nodes/NAME/params/PARAM
// is node 'NAME' param 'PARAM'. An empty step is an object whose first key is not read yet.
Place placeOf(const std::vector<std::string>& path) {
  if (path.empty() || path[0].empty()) return {};
  const std::string& top = path[0];
  const auto step = [&](std::size_t i) { return i < path.size() ? path[i] : std::string(); };
  if ((top == "nodes" || top == "ui") && !step(1).empty()) {
    Place place{step(1), ""};
    if (top == "ui")
      place.where = step(2).empty() ? "ui" : "ui " + jsonKey(step(2));
    else if (step(2) == "params" && !step(3).empty())
      place.where = "param " + quoteText(step(3));
    else if (!step(2).empty())
      place.where = jsonKey(step(2));
    return place;
  }
  const std::string index = step(1);  // of a connection, when "connections" is the array it must be
  if (top == "connections" && !index.empty() && index.size() < 10 &&
      std::all_of(index.begin(), index.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return {"", "connection " + std::to_string(std::stoul(index) + 1)};
  // Inside an object whose first key is not read yet, the top key would say too much.
  if (path.size() == 1 || !index.empty()) return {"", jsonKey(top)};
  return {};
}

// Builds the document as nlohmann's DOM parser does, and keeps the path of keys (and array
// indices) to where the parser is, so that an error names the node and param it happened in.
// It refuses what the DOM parser lets through: a duplicate key (the DOM keeps the last one
// silently) and nesting deeper than a graph file needs (every level costs memory).
class GraphSaxParser {
 public:
  struct Problem {
    std::vector<std::string> path;
    std::string cause;
  };

  explicit GraphSaxParser(json& root) : dom_(root, /*allow_exceptions=*/false) {}

  bool null() {
    enterValue();
    return dom_.null();
  }
  bool boolean(bool value) {
    enterValue();
    return dom_.boolean(value);
  }
  bool number_integer(json::number_integer_t value) {
    enterValue();
    return dom_.number_integer(value);
  }
  bool number_unsigned(json::number_unsigned_t value) {
    enterValue();
    return dom_.number_unsigned(value);
  }
  bool number_float(json::number_float_t value, const json::string_t& text) {
    enterValue();
    return dom_.number_float(value, text);
  }
  bool string(json::string_t& value) {
    enterValue();
    return dom_.string(value);
  }
  bool binary(json::binary_t& value) {
    enterValue();
    return dom_.binary(value);
  }

  bool start_object(std::size_t size) {
    enterValue();
    return open(false) && dom_.start_object(size);
  }
  bool key(json::string_t& key) {
    Frame& frame = frames_.back();
    frame.step = key;
    if (!frame.keys.insert(key).second) return fail("duplicate key " + jsonKey(key));
    return dom_.key(key);
  }
  bool end_object() {
    frames_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t size) {
    enterValue();
    return open(true) && dom_.start_array(size);
  }
  bool end_array() {
    frames_.pop_back();
    return dom_.end_array();
  }

  bool parse_error(std::size_t, const std::string& token, const nlohmann::detail::exception& e) {
    // 406: a number that no double holds, such as 1e309.
    if (e.id == 406) return fail("number out of range: " + escapeText(token));
    const std::string what = e.what();
    const auto at = what.find("parse error");
    return fail("malformed JSON: " +
                escapeText(at == std::string::npos ? what : what.substr(at), 2 * kExcerptLimit));
  }

  const std::optional<Problem>& problem() const { return problem_; }

 private:
  // An object's or array's place in the path: the key read last, or the index of the element.
  struct Frame {
    bool array = false;
    std::size_t elements = 0;
    std::string step;
    std::set<std::string> keys;
  };

  // In an array, a value is the next element.
  void enterValue() {
    if (!frames_.empty() && frames_.back().array)
      frames_.back().step = std::to_string(frames_.back().elements++);
  }
  bool open(bool array) {
    if (frames_.size() == kMaxJsonDepth)
      return fail("nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    frames_.push_back({array, 0, "", {}});
    return true;
  }
  bool fail(std::string cause) {
    std::vector<std::string> path;
    for (const auto& frame : frames_)
      path.push_back(frame.step);
    problem_ = Problem{std::move(path), std::move(cause)};
    return false;
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Frame> frames_;
  std::optional<Problem> problem_;
};

json parseJson(const std::string& text, const std::filesystem::path& file) {
  // nlohmann's lexer ends the input at a NUL byte and would ignore what follows; JSON text holds
  // none (a string writes it as \u0000).
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw GraphError(file, "", "", "malformed JSON: a NUL byte at byte " + std::to_string(nul + 1));
  json root;
  GraphSaxParser parser(root);
  if (json::sax_parse(text, &parser)) return root;
  if (const auto& problem = parser.problem()) {
    const Place place = placeOf(problem->path);
    throw GraphError(file, place.node, place.where, problem->cause);
  }
  throw GraphError(file, "", "", "malformed JSON");
}

bool validNodeName(const std::string& name) {
  if (name.empty()) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

ParamValue paramFromJson(const json& value) {
  if (value.is_boolean()) return value.get<bool>();
  // An integer beyond int64 is read as the double it is near; no int param reaches it.
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
    return value.get<double>();
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
  throw std::invalid_argument(std::string(value.is_null() ? "null" : "an object") +
                              " is not a parameter value");
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
        std::string("connection '") + key + "' must be \"node.port\", got " + jsonKey(text));
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

// An integer key's value that fits an int (format and type versions).
int requireInt(const Graph& graph, const std::string& node, const json& object, const char* key) {
  const json value =
      require<json>(graph, node, object, key, &json::is_number_integer, "an integer");
  // Compared as the file holds it: a huge unsigned value would read as a negative int64.
  const bool fits =
      value.is_number_unsigned()
          ? value.get<std::uint64_t>() <= std::uint64_t(std::numeric_limits<int>::max())
          : value.get<std::int64_t>() >= std::numeric_limits<int>::min();
  if (!fits)
    throw GraphError(graph.file, node, jsonKey(key), "number out of range: " + value.dump());
  return int(value.get<std::int64_t>());
}

// A ui coordinate: absent is 0.
double uiCoordinate(const Graph& graph, const std::string& node, const json& entry,
                    const char* axis) {
  const auto it = entry.find(axis);
  if (it == entry.end()) return 0;
  if (!it->is_number())
    throw GraphError(graph.file, node, "ui " + jsonKey(axis), "must be a number");
  return it->get<double>();
}

void rejectUnknownKeys(const Graph& graph, const std::string& node, const json& object,
                       std::initializer_list<const char*> known) {
  for (const auto& item : object.items()) {
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return item.key() == k; }))
      throw GraphError(graph.file, node, "", "unknown key " + jsonKey(item.key()));
  }
}

GraphNode readNode(Graph& graph, const std::string& name, const json& entry) {
  if (!entry.is_object()) throw GraphError(graph.file, name, "", "must be an object");
  rejectUnknownKeys(graph, name, entry, {"type", "typeVersion", "params"});
  GraphNode node;
  node.type = require<std::string>(graph, name, entry, "type", &json::is_string, "a string");
  node.typeVersion = requireInt(graph, name, entry, "typeVersion");
  const auto params = entry.find("params");
  if (params == entry.end()) return node;
  if (!params->is_object()) throw GraphError(graph.file, name, "", "\"params\" must be an object");
  std::vector<std::string>& order = graph.keyOrder.params[name];
  for (const auto& [param, value] : params->items()) {
    order.push_back(param);
    try {
      node.params[param] = paramFromJson(value);
    } catch (const std::exception& e) {
      throw GraphError(graph.file, name, "param " + quoteText(param), e.what());
    }
  }
  return node;
}

// What the explicit checks missed, still named by file and node rather than by nlohmann's text.
GraphError unexpectedJson(const Graph& graph, const std::string& node, const json::exception& e) {
  return GraphError(graph.file, node, "", "unexpected JSON: " + escapeText(e.what()));
}

void readNodes(Graph& graph, const json& root) {
  const auto nodes = root.find("nodes");
  if (nodes == root.end()) return;
  if (!nodes->is_object())
    throw GraphError(graph.file, "", "", "\"nodes\" must be an object keyed by node name");
  for (const auto& [name, entry] : nodes->items()) {
    if (!validNodeName(name))
      throw GraphError(graph.file, name, "",
                       "node names may use only letters, digits, '_' and '-'");
    graph.keyOrder.nodes.push_back(name);
    try {
      graph.nodes.emplace(name, readNode(graph, name, entry));
    } catch (const json::exception& e) {
      throw unexpectedJson(graph, name, e);
    }
  }
}

void readConnections(Graph& graph, const json& root) {
  const auto connections = root.find("connections");
  if (connections == root.end()) return;
  if (!connections->is_array())
    throw GraphError(graph.file, "", "", "\"connections\" must be an array");
  for (const auto& entry : *connections) {
    if (!entry.is_object() || !entry.contains("from") || !entry.contains("to"))
      throw GraphError(graph.file, "", "",
                       "each connection must be {\"from\": \"node.port\", \"to\": \"node.port\"}");
    graph.connections.push_back({parseEndpoint(graph, entry.at("from"), "from"),
                                 parseEndpoint(graph, entry.at("to"), "to")});
  }
}

void readUi(Graph& graph, const json& root) {
  const auto ui = root.find("ui");
  if (ui == root.end()) return;
  if (!ui->is_object())
    throw GraphError(graph.file, "", "", "\"ui\" must be an object keyed by node name");
  for (const auto& [name, entry] : ui->items()) {
    if (!entry.is_object()) throw GraphError(graph.file, name, "", "ui entry must be an object");
    graph.keyOrder.ui.push_back(name);
    try {
      graph.ui[name] = {uiCoordinate(graph, name, entry, "x"),
                        uiCoordinate(graph, name, entry, "y")};
    } catch (const json::exception& e) {
      throw unexpectedJson(graph, name, e);
    }
  }
}

// The keys of `map` in the order `order` names them (those it names that are still there), then
// the others sorted: a graph read from a file is written back in the file's order.
template <typename Map>
std::vector<std::string> inFileOrder(const Map& map, const std::vector<std::string>& order) {
  std::vector<std::string> keys;
  std::set<std::string> placed;
  for (const std::string& key : order)
    if (map.count(key) && placed.insert(key).second) keys.push_back(key);
  for (const auto& entry : map)
    if (!placed.count(entry.first)) keys.push_back(entry.first);
  return keys;
}

// An object or array holding numbers, strings and booleans alone (a row, a connection, a ui
// position) is written on one line; a node's params are not, so that each param takes its own.
bool writtenOnOneLine(const json& value, const std::string& key) {
  if (value.empty() || key == "params") return value.empty();
  return std::all_of(value.begin(), value.end(),
                     [](const json& item) { return item.is_primitive(); });
}

// Two-space indented JSON, as nlohmann's dump(2), except that a row of numbers (a vector, a dab),
// a connection and a ui position take one line each: editing one changes one line of the file.
void writeJson(const json& value, int indent, std::string& out, const std::string& key = {}) {
  if (value.is_primitive()) {
    out += value.dump();
    return;
  }
  const bool object = value.is_object();
  out += object ? '{' : '[';
  if (writtenOnOneLine(value, key)) {
    for (auto item = value.begin(); item != value.end(); ++item) {
      if (item != value.begin()) out += ", ";
      if (object) out += json(item.key()).dump() + ": ";
      out += item->dump();
    }
    out += object ? '}' : ']';
    return;
  }
  for (auto item = value.begin(); item != value.end(); ++item) {
    out += item == value.begin() ? "\n" : ",\n";
    out.append(std::size_t(indent + 2), ' ');
    const std::string itemKey = object ? item.key() : std::string();
    if (object) out += json(itemKey).dump() + ": ";
    writeJson(*item, indent + 2, out, itemKey);
  }
  out += '\n';
  out.append(std::size_t(indent), ' ');
  out += object ? '}' : ']';
}

}  // namespace

Graph parseGraph(const std::string& text, const std::filesystem::path& file) {
  Graph graph;
  graph.file = file;
  const json root = parseJson(text, file);
  if (!root.is_object()) throw GraphError(file, "", "", "a graph file must hold a JSON object");
  rejectUnknownKeys(graph, "", root, {"format", "formatVersion", "nodes", "connections", "ui"});
  if (root.value("format", json()) != kGraphFormat)
    throw GraphError(file, "", "", "not a GeoBrush graph (\"format\" must be \"geobrush-graph\")");
  const int version = requireInt(graph, "", root, "formatVersion");
  if (version > kGraphFormatVersion)
    throw GraphError(file, "", "",
                     "formatVersion " + std::to_string(version) +
                         " was written by a newer GeoBrush; this one reads up to " +
                         std::to_string(kGraphFormatVersion));
  if (version < 1) throw GraphError(file, "", "", "formatVersion must be >= 1");
  readNodes(graph, root);
  readConnections(graph, root);
  readUi(graph, root);
  return graph;
}

Graph readGraphFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw GraphError(path, "", "", "is a folder, not a graph file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw GraphError(path, "", "",
                     std::filesystem::exists(path, ec) ? "cannot read the file" : "no such file");
  // Read through the stream, not by the file's size: devices and pipes have none.
  std::string text;
  std::string buffer(std::size_t(1) << 16, '\0');
  while (in && text.size() <= kMaxGraphFileBytes) {
    const auto wanted = std::min(buffer.size(), kMaxGraphFileBytes + 1 - text.size());
    in.read(buffer.data(), std::streamsize(wanted));
    text.append(buffer.data(), std::size_t(in.gcount()));
  }
  if (in.bad()) throw GraphError(path, "", "", "cannot read the file");
  if (text.size() > kMaxGraphFileBytes)
    throw GraphError(path, "", "",
                     "larger than " + std::to_string(kMaxGraphFileBytes >> 20) +
                         " MiB: not a graph file (graph files are kilobytes)");
  return parseGraph(text, path);
}

std::string serializeGraph(const Graph& graph, const NodeRegistry* registry,
                           DefaultParams defaults) {
  json root = json::object();
  root["format"] = kGraphFormat;
  root["formatVersion"] = kGraphFormatVersion;
  json nodes = json::object();
  for (const std::string& name : inFileOrder(graph.nodes, graph.keyOrder.nodes)) {
    const GraphNode& node = graph.nodes.at(name);
    const NodeType* type = registry ? registry->find(node.type) : nullptr;
    const auto paramOrder = graph.keyOrder.params.find(name);
    json params = json::object();
    for (const std::string& param : inFileOrder(
             node.params, paramOrder == graph.keyOrder.params.end() ? std::vector<std::string>{}
                                                                    : paramOrder->second)) {
      const ParamValue& value = node.params.at(param);
      const ParamDecl* decl = type ? type->findParam(param) : nullptr;
      if (decl && defaults == DefaultParams::Omit && decl->defaultValue == value) continue;
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
    for (const std::string& name : inFileOrder(graph.ui, graph.keyOrder.ui)) {
      const UiPosition& pos = graph.ui.at(name);
      ui[name] = {{"x", pos.x}, {"y", pos.y}};
    }
    root["ui"] = ui;
  }
  std::string text;
  writeJson(root, 0, text);
  return text + "\n";
}

void writeGraphFile(const Graph& graph, const std::filesystem::path& path,
                    const NodeRegistry* registry, DefaultParams defaults) {
  const std::string text = serializeGraph(graph, registry, defaults);
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
