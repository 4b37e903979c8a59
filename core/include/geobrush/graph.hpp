// The graph model and its JSON file form (see DESIGN.md, "Graph files").
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/param.hpp"

namespace geobrush {

class NodeRegistry;

inline constexpr std::string_view kGraphFormat = "geobrush-graph";
inline constexpr int kGraphFormatVersion = 1;

struct GraphNode {
  std::string type;
  int typeVersion = 1;
  ParamMap params;  // only the values that differ from the defaults
};

struct Endpoint {
  std::string node;
  std::string port;
  bool operator==(const Endpoint&) const = default;
};

struct Connection {
  Endpoint from;  // an output port
  Endpoint to;    // an input port
  bool operator==(const Connection&) const = default;
};

struct UiPosition {
  double x = 0;
  double y = 0;
  bool operator==(const UiPosition&) const = default;
};

struct Graph {
  std::map<std::string, GraphNode> nodes;  // keyed by stable name
  std::vector<Connection> connections;
  std::map<std::string, UiPosition> ui;
  // The order of the nodes, of each node's params and of the ui entries in the file read: saving
  // keeps it, and writes what it does not name after, sorted by name.
  struct KeyOrder {
    std::vector<std::string> nodes;
    std::map<std::string, std::vector<std::string>> params;  // by node name
    std::vector<std::string> ui;
  };
  KeyOrder keyOrder;
  // The file it was read from; relative paths in params resolve against its folder.
  std::filesystem::path file;

  std::filesystem::path baseDir() const;
  // The connection feeding an input port, if any.
  const Connection* source(const std::string& node, const std::string& port) const;
};

// A problem with a graph file or its structure: exit status 2 in the CLI.
// The message is one line naming the file, node and port where known.
class GraphError : public std::runtime_error {
 public:
  GraphError(const std::filesystem::path& file, const std::string& node, const std::string& where,
             const std::string& cause);
  const std::filesystem::path& file() const { return file_; }
  const std::string& node() const { return node_; }
  const std::string& where() const { return where_; }  // "param 'x'", "input 'mesh'", or empty
  const std::string& cause() const { return cause_; }

 private:
  std::filesystem::path file_;
  std::string node_;
  std::string where_;
  std::string cause_;
};

// Reads and parses a graph file (no registry needed). Throws GraphError.
Graph readGraphFile(const std::filesystem::path& path);
Graph parseGraph(const std::string& json, const std::filesystem::path& file);
// Whether serializeGraph leaves out params equal to their declared defaults.
enum class DefaultParams { Omit, Keep };
// Writes the graph as JSON in the order of the file it was read from (see Graph::keyOrder; what
// the file did not name, sorted), two-space indented, with a row of numbers, a connection and a
// ui position on one line each. With a registry, list params are written in the rows they declare
// (dabs of 4 numbers), and params equal to their defaults are left out unless `defaults` is Keep.
std::string serializeGraph(const Graph& graph, const NodeRegistry* registry = nullptr,
                           DefaultParams defaults = DefaultParams::Omit);
// Atomic write of serializeGraph (temporary file, then rename).
void writeGraphFile(const Graph& graph, const std::filesystem::path& path,
                    const NodeRegistry* registry = nullptr,
                    DefaultParams defaults = DefaultParams::Omit);

// Makes a parsed graph ready to evaluate against the loaded node types:
// upgrades older typeVersions with the types' upgrade functions, converts
// params to their declared kinds and checks them, and checks every
// connection (nodes and ports exist, types match, one source per input,
// required inputs connected, no cycles). Throws GraphError. A graph being
// edited may leave required inputs open (`requireInputs = false`); it is
// then checked but cannot be evaluated.
void prepareGraph(Graph& graph, const NodeRegistry& registry, bool requireInputs = true);

// Throws GraphError when two OutputPath params of the graph (of two nodes, or two of one node)
// name the same file, naming both nodes and the file: each would report writing it. Relative
// paths resolve against `outputDir`; with none, only paths that name the same file wherever the
// outputs go are compared (relative with relative, absolute with absolute). prepareGraph checks
// without a folder; the evaluator checks with its output folder.
void checkOutputPaths(const Graph& graph, const NodeRegistry& registry,
                      const std::filesystem::path& outputDir = {});

// Sets NODE.PARAM from its command-line text form ("--set NODE.PARAM=VALUE").
// Throws GraphError.
void setParamFromText(Graph& graph, const NodeRegistry& registry, const std::string& assignment);

// Node names in a deterministic topological order (ties by name). Throws
// GraphError on a cycle.
std::vector<std::string> topologicalOrder(const Graph& graph);

}  // namespace geobrush
