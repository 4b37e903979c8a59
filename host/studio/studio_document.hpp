// The studio's model of one open graph file: the graph as read (kept whole, also where a node's
// plugin is missing, so that it saves back unchanged), which nodes are missing, and the state
// of each node after the last evaluation. No widgets here: tests drive it directly.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/param.hpp"
#include "geobrush/registry.hpp"

namespace geobrush::studio {

enum class NodeState { Idle, Ok, Warning, Error, Missing };

struct NodeStatus {
  NodeState state = NodeState::Idle;
  std::string message;  // the error, the warnings, or why the node is missing
  double seconds = 0;
};

class StudioDocument {
 public:
  explicit StudioDocument(const NodeRegistry& registry) : registry_(registry) {}

  // An empty, untitled graph (saved with save()).
  void newGraph();
  // Reads a graph file. A node whose type no plugin provides stays in the graph, marked
  // missing; the rest of the graph is checked as the CLI checks it. Returns the error (one line
  // naming the file, node and port) or an empty string; on error the document is unchanged.
  std::string open(const std::filesystem::path& path);
  // Writes the graph in the CLI's format (UI positions in the "ui" block); saved in another
  // folder, its relative input paths are rewritten to name the same files from there. Returns
  // the error or an empty string.
  std::string save(const std::filesystem::path& path);

  const Graph& graph() const { return graph_; }
  Graph& graph() { return graph_; }
  const std::filesystem::path& path() const { return path_; }
  const std::set<std::string>& missingNodes() const { return missing_; }
  // Whether the graph differs from the file it was opened from or last saved to (an untitled
  // graph: from the empty graph); undoing back to that graph clears it.
  bool modified() const;
  bool evaluable() const { return missing_.empty(); }

  // Graph edits. Each returns an error for the user (naming the node and port) and leaves the
  // graph unchanged, or returns an empty string; a successful edit can be undone.
  // A node of `typeId` at (x, y), named after the type and numbered to be unique.
  std::string addNode(const std::string& typeId, double x, double y, std::string* name = nullptr);
  // Removes the nodes and every connection to or from them.
  std::string removeNodes(const std::vector<std::string>& names);
  // Connects an output to an input whose value types match; a connection already feeding the
  // input is replaced. Refuses unknown nodes or ports, mismatched types and cycles.
  std::string connect(const Endpoint& from, const Endpoint& to);
  // A param value, checked against the node type's declaration (kind, range, choices).
  std::string setParam(const std::string& node, const std::string& param, ParamValue value);
  void moveNode(const std::string& node, double x, double y);
  // A param's value as the node computes with it (its default where the file sets none); none
  // for an unknown node or param.
  std::optional<ParamValue> param(const std::string& node, const std::string& param) const;

  // A gesture (a brush stroke, a drag) makes many edits that undo as one: those between
  // beginGesture() and endGesture(). Undo and redo end a gesture first.
  void beginGesture();
  void endGesture();
  bool inGesture() const { return gestureStart_ != nullptr; }

  // Steps back through the edits and forward again; false when there is nothing to step to.
  bool undo();
  bool redo();
  bool canUndo() const { return !undo_.empty() || gestureChanged_; }
  bool canRedo() const { return !redo_.empty(); }
  // What undo and redo would change, in words (describeEdit); empty when there is nothing to.
  std::string undoText() const;
  std::string redoText() const;

  // The statuses after an evaluation (or the missing marks); every node has one.
  std::map<std::string, NodeStatus> statuses(const EvalReport* report) const;

 private:
  const NodeRegistry& registry_;
  Graph graph_;
  std::filesystem::path path_;
  std::set<std::string> missing_;
  Graph saved_;                          // as opened or last saved
  std::vector<Graph> undo_, redo_;       // the graph before each edit, and the edits undone
  std::unique_ptr<Graph> gestureStart_;  // the graph before the gesture under way
  bool gestureChanged_ = false;

  Graph rebased(const std::filesystem::path& path) const;
  // Replaces the graph by an edited copy, keeping the current one for undo.
  void commit(Graph edited);
  void updateMissing();
};

// An edit from `before` to `after` in words, for the Undo and Redo commands: the nodes added or
// removed, else the params changed ("set strokes.dabs"), else the connections made or removed,
// else the nodes moved.
std::string describeEdit(const Graph& before, const Graph& after);

}  // namespace geobrush::studio
