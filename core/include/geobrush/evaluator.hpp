// Pull-based, cached evaluation of a graph.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/graph.hpp"
#include "geobrush/hash.hpp"
#include "geobrush/value.hpp"

namespace geobrush {

class NodeRegistry;

struct EvalOptions {
  // Where OutputPath params resolve; empty: the graph file's folder.
  std::filesystem::path outputDir;
  // Nodes to evaluate, with everything upstream; empty: every node.
  std::vector<std::string> targets;
  // Called from the evaluating thread with the node name and its progress.
  std::function<void(const std::string& node, double fraction)> progress;
  const std::atomic<bool>* cancel = nullptr;
  // Recompute every output that came from a node's history (a warm start) or from such an
  // output, each node with a fresh instance: the results then equal a fresh evaluator's, as
  // `geobrush run` computes them, bit for bit.
  bool settle = false;
};

struct NodeRun {
  std::string node;
  std::string type;
  Hash key = 0;
  double seconds = 0;
  bool cacheHit = false;
  bool failed = false;
  // The outputs depend on a node's history (its own warm start or one upstream).
  bool history = false;
  std::vector<std::string> warnings;
};

struct EvalReport {
  bool ok = true;
  bool cancelled = false;
  std::string error;          // one line naming the file, node and port
  std::string errorNode;      // the node that failed, where one did
  std::string errorWhere;     // the port or param it names ("param 'path'"), or empty
  std::vector<NodeRun> runs;  // in evaluation order
  std::vector<std::filesystem::path> filesWritten;

  int computed() const;
  int cacheHits() const;
  // Some output depends on a node's history: a settling evaluation would recompute it.
  bool historyDependent() const;
};

class Evaluator {
 public:
  explicit Evaluator(const NodeRegistry& registry);
  ~Evaluator();

  // Evaluates a graph that went through prepareGraph. Never throws for a
  // node's failure: it is reported, nothing is written, and the outputs of
  // the nodes that succeeded stay cached.
  EvalReport evaluate(const Graph& graph, const EvalOptions& options = {});

  // An output of the last evaluate() call, or null.
  ValuePtr output(const std::string& node, const std::string& port) const;

  // The cache key of every node: a hash of its type id, type version,
  // effective params (input files by size and time) and the keys of its inputs.
  std::map<std::string, Hash> nodeKeys(const Graph& graph, const EvalOptions& options = {}) const;

  // Number of node computations (cache misses) since construction.
  std::uint64_t computeCount() const { return computeCount_; }
  // Derived data (Context::derived) built since construction, and held now.
  std::uint64_t derivedBuildCount() const;
  std::size_t derivedHeld() const;
  // Retired outputs kept for their nodes to recycle (Context::recycle).
  std::size_t recycledHeld() const;
  void clearCache();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::uint64_t computeCount_ = 0;
};

// Every Metrics output of the evaluator's last evaluation of `graph`: its values as
// "node.name" (sorted), and its notes as "node: note".
struct CollectedMetrics {
  std::map<std::string, double> values;
  std::vector<std::string> notes;
};
CollectedMetrics collectMetrics(const Graph& graph, const NodeRegistry& registry,
                                const Evaluator& evaluator);

}  // namespace geobrush
