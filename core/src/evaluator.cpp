#include "geobrush/evaluator.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <unordered_map>

#include "atomic_file.hpp"
#include "geobrush/derived_store.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/text.hpp"
#include "geobrush/values.hpp"

namespace geobrush {
namespace {

using Outputs = std::map<std::string, ValuePtr>;
using InputKeys = std::map<std::string, Hash, std::less<>>;

std::filesystem::path resolvePath(const std::string& text, const std::filesystem::path& base) {
  if (text.empty()) return {};
  std::filesystem::path path(text);
  return (path.is_absolute() ? path : base / path).lexically_normal();
}

const ParamValue& effectiveParam(const GraphNode& node, const ParamDecl& decl) {
  auto it = node.params.find(decl.name);
  return it == node.params.end() ? decl.defaultValue : it->second;
}

void hashParam(Hasher& hasher, const ParamValue& value) {
  hasher.u64(value.index());
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>)
          hasher.u64(v);
        else if constexpr (std::is_same_v<T, std::int64_t>)
          hasher.u64(std::uint64_t(v));
        else if constexpr (std::is_same_v<T, double>)
          hasher.f64(v);
        else if constexpr (std::is_same_v<T, std::string>)
          hasher.str(v);
        else {
          hasher.u64(v.size());
          for (double d : v)
            hasher.f64(d);
        }
      },
      value);
}

// An input file enters the key by its size and modification time, so editing
// the file invalidates what was computed from it.
void hashFileState(Hasher& hasher, const std::filesystem::path& path) {
  struct stat info {};
  if (path.empty() || ::stat(path.c_str(), &info) != 0) {
    hasher.u64(0);
    return;
  }
  hasher.u64(1).u64(std::uint64_t(info.st_size)).u64(std::uint64_t(info.st_mtim.tv_sec));
  hasher.u64(std::uint64_t(info.st_mtim.tv_nsec));
}

// Where each input port gets its value: (node, port) -> upstream output.
// Built once per call so that large graphs stay linear.
using SourceIndex = std::map<std::pair<std::string, std::string>, Endpoint>;

SourceIndex indexSources(const Graph& graph) {
  SourceIndex sources;
  for (const auto& c : graph.connections)
    sources.emplace(std::pair{c.to.node, c.to.port}, c.from);
  return sources;
}

std::vector<std::string> inputNames(const NodeType& type) {
  std::vector<std::string> names;
  for (const auto& port : type.inputs)
    names.push_back(port.name);
  return names;
}

const Endpoint* findSource(const SourceIndex& sources, const std::string& node,
                           const std::string& port) {
  auto it = sources.find({node, port});
  return it == sources.end() ? nullptr : &it->second;
}

struct PendingFile {
  std::string node;  // the node that wrote it, for messages
  std::filesystem::path target;
  std::filesystem::path tmp;
};

class EvalContext final : public Context {
 public:
  // `preparing`: the context of Node::prepare, which runs off the evaluating thread: no outputs,
  // no files, no progress reports.
  EvalContext(const NodeType& type, const GraphNode& node, const std::string& name,
              const Outputs& inputs, InputKeys inputKeys, DerivedStore& derived, RecycleBin& bin,
              std::mutex& binMutex, const std::filesystem::path& baseDir,
              const std::filesystem::path& outputDir, const EvalOptions& options,
              bool preparing = false)
      : type_(type),
        node_(node),
        name_(name),
        inputs_(inputs),
        inputKeys_(std::move(inputKeys)),
        derived_(derived),
        bin_(bin),
        binMutex_(binMutex),
        baseDir_(baseDir),
        outputDir_(outputDir),
        options_(options),
        preparing_(preparing) {}

  std::filesystem::path path(std::string_view name) const override {
    const ParamDecl* decl = type_.findParam(name);
    if (!decl || (decl->kind != ParamKind::InputPath && decl->kind != ParamKind::OutputPath))
      throw NodeError::param(name, "is not a path parameter of '" + type_.id + "'");
    const auto& text = std::get<std::string>(effectiveParam(node_, *decl));
    return resolvePath(text, decl->kind == ParamKind::InputPath ? baseDir_ : outputDir_);
  }

  void out(std::string_view port, ValuePtr value) override {
    if (preparing_)
      throw NodeError::output(port, "was set in prepare(); outputs come from compute()");
    const PortDecl* decl = type_.findOutput(port);
    if (!decl) throw NodeError::output(port, "'" + type_.id + "' declares no such output");
    if (!value) throw NodeError::output(port, "was set to nothing");
    if (value->typeId() != decl->typeId)
      throw NodeError::output(port, "was set to a " + std::string(value->typeId()) +
                                        " but is declared as " + decl->typeId);
    outputs_[std::string(port)] = std::move(value);
    recyclable_.erase(std::string(port));  // outRecyclable keeps it again
  }

  void progress(double fraction) override {
    if (!options_.progress || preparing_) return;
    fraction = std::clamp(fraction, 0.0, 1.0);
    if (relayed_)
      relayed_->store(fraction, std::memory_order_relaxed);
    else
      options_.progress(name_, fraction);
  }
  // Off the evaluating thread: progress goes to `fraction`, which the evaluating thread reports.
  void relayProgressThrough(std::atomic<double>* fraction) { relayed_ = fraction; }
  bool cancelled() const override {
    return options_.cancel && options_.cancel->load(std::memory_order_relaxed);
  }
  void warn(const std::string& message) override { warnings_.push_back(message); }

  void writeFile(const std::filesystem::path& path,
                 const std::function<void(const std::filesystem::path& tmp)>& write) override {
    if (preparing_) throw NodeError("files are written in compute(), not in prepare()");
    if (path.empty()) throw NodeError("no output file given");
    std::error_code ec;
    if (!std::filesystem::is_directory(path.parent_path(), ec))
      throw NodeError("cannot write " + quotePath(path) + ": folder " +
                      quotePath(path.parent_path()) + " does not exist");
    std::filesystem::path file;
    try {
      file = replaceableTarget(path);
    } catch (const std::runtime_error& e) {
      throw NodeError(pathParamNaming(path), e.what());
    }
    const auto tmp = temporaryPathFor(file);
    pending_.push_back({name_, path, tmp});
    write(tmp);
    if (!std::filesystem::exists(tmp, ec))
      throw NodeError("writing " + quotePath(path) + " produced no file");
  }

  // "param 'NAME'" for the OutputPath param that names `path`, so that a failed write names the
  // param it came from; empty when none does.
  std::string pathParamNaming(const std::filesystem::path& path) const {
    for (const auto& decl : type_.params)
      if (decl.kind == ParamKind::OutputPath &&
          resolvePath(std::get<std::string>(effectiveParam(node_, decl)), outputDir_) == path)
        return NodeError::param(decl.name, "").where();
    return "";
  }

  Outputs& outputs() { return outputs_; }
  // The outputs published with outRecyclable, by port.
  std::map<std::string, RecyclableValue>& recyclable() { return recyclable_; }
  std::vector<std::string>& warnings() { return warnings_; }
  std::vector<PendingFile>& pending() { return pending_; }

 protected:
  ValuePtr inputValue(std::string_view port) const override {
    if (!type_.findInput(port))
      throw NodeError::input(port, "'" + type_.id + "' declares no such input");
    auto it = inputs_.find(std::string(port));
    return it == inputs_.end() ? nullptr : it->second;
  }
  const ParamValue& paramValue(std::string_view name) const override {
    const ParamDecl* decl = type_.findParam(name);
    if (!decl) throw NodeError::param(name, "'" + type_.id + "' declares no such parameter");
    return effectiveParam(node_, *decl);
  }
  Hash inputKey(std::string_view port) const override {
    if (!type_.findInput(port))
      throw NodeError::input(port, "'" + type_.id + "' declares no such input");
    auto it = inputKeys_.find(port);
    return it == inputKeys_.end() ? 0 : it->second;
  }
  std::shared_ptr<const void> derivedValue(
      Hash key, const std::vector<ValuePtr>& derivedFrom,
      const std::function<std::shared_ptr<const void>()>& build) override {
    return derived_.get(key, derivedFrom, build);
  }
  void keepRecyclable(std::string_view port, RecyclableValue value) override {
    recyclable_[std::string(port)] = std::move(value);
  }
  RecyclableValue recycledValue(
      std::string_view port, const std::function<bool(const RecyclableValue&)>& accepts) override {
    if (!type_.findOutput(port))
      throw NodeError::output(port, "'" + type_.id + "' declares no such output");
    const std::lock_guard lock(binMutex_);
    return bin_.take(name_, port, accepts);
  }

 private:
  const NodeType& type_;
  const GraphNode& node_;
  const std::string& name_;
  const Outputs& inputs_;
  InputKeys inputKeys_;
  DerivedStore& derived_;
  RecycleBin& bin_;
  std::mutex& binMutex_;  // nodes computing at the same time share the bin
  std::atomic<double>* relayed_ = nullptr;
  std::filesystem::path baseDir_;
  std::filesystem::path outputDir_;
  const EvalOptions& options_;
  bool preparing_ = false;
  Outputs outputs_;
  std::map<std::string, RecyclableValue> recyclable_;
  std::vector<std::string> warnings_;
  std::vector<PendingFile> pending_;
};

// A node's failure as remembered by the cache: the same key fails the same way.
struct Failure {
  std::string where;
  std::string message;
};

void fail(EvalReport& report, const GraphError& error) {
  report.ok = false;
  report.error = error.what();
  report.errorNode = error.node();
  report.errorWhere = error.where();
}

void fail(EvalReport& report, const Graph& graph, const std::string& node, const Failure& failure) {
  fail(report, GraphError(graph.file, node, failure.where, failure.message));
}

// Runs a node's prepare() or compute(); what it throws becomes its failure.
template <typename Work>
std::optional<Failure> guarded(const Work& work, bool& cancelled) {
  try {
    work();
  } catch (const Cancelled&) {
    cancelled = true;
    return Failure{"", "cancelled"};
  } catch (const NodeError& e) {
    return Failure{e.where(), e.what()};
  } catch (const std::exception& e) {
    return Failure{"", std::string("failed: ") + e.what()};
  } catch (...) {
    return Failure{"", "failed with an unknown exception"};
  }
  return std::nullopt;
}

// A node's prepare(), run ahead on another thread or just before its compute().
struct Preparation {
  Outputs inputs;  // the prepareInputs that are connected
  std::unique_ptr<EvalContext> context;
  std::future<void> running;  // valid while it runs ahead
  std::optional<Failure> failure;
  bool cancelled = false;
  double seconds = 0;

  void run(Node& node) {
    const auto start = std::chrono::steady_clock::now();
    failure = guarded([&] { node.prepare(*context); }, cancelled);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  void finish() {
    if (running.valid()) running.get();
  }
};

}  // namespace

int EvalReport::computed() const {
  int count = 0;
  for (const auto& run : runs)
    count += !run.cacheHit;
  return count;
}

bool EvalReport::historyDependent() const {
  for (const auto& run : runs)
    if (run.history) return true;
  return false;
}

int EvalReport::cacheHits() const {
  int count = 0;
  for (const auto& run : runs)
    count += run.cacheHit;
  return count;
}

struct Evaluator::Impl {
  struct Entry {
    Outputs outputs;
    std::optional<Failure> failure;
    std::vector<std::string> warnings;
    std::uint64_t lastUsed = 0;
    bool history = false;  // the outputs depend on a node's history (see NodeRun::history)
    std::string node;      // the node that computed it
    std::map<std::string, RecyclableValue> recyclable;  // by port: see Context::outRecyclable
  };
  struct Instance {
    const NodeType* type = nullptr;
    std::unique_ptr<Node> node;
  };
  class Run;

  const NodeRegistry& registry;
  std::unordered_map<Hash, Entry> cache;
  std::map<std::string, Instance> instances;
  std::map<std::string, Outputs> lastOutputs;
  DerivedStore derived;
  RecycleBin bin;  // what retired entries published as recyclable
  std::mutex binMutex;
  std::uint64_t generation = 0;

  explicit Impl(const NodeRegistry& r) : registry(r) {}

  std::filesystem::path outputDir(const Graph& graph, const EvalOptions& options) const {
    return options.outputDir.empty() ? graph.baseDir()
                                     : std::filesystem::absolute(options.outputDir);
  }

  Node& instance(const std::string& name, const NodeType& type, bool fresh) {
    Instance& slot = instances[name];
    if (slot.type != &type || !slot.node || fresh) {
      slot.type = &type;
      slot.node = type.create();
    }
    return *slot.node;
  }
};

// One call of Evaluator::evaluate, in stages: plan (order, keys, the nodes needed), then each
// node in order (a cached result, or its preparation and compute), then the files all together,
// then what the cache keeps.
class Evaluator::Impl::Run {
 public:
  Run(Evaluator& evaluator, const Graph& graph, const EvalOptions& options)
      : evaluator_(evaluator),
        impl_(*evaluator.impl_),
        graph_(graph),
        options_(options),
        generation_(++impl_.generation),
        baseDir_(graph.baseDir()),
        outputDir_(impl_.outputDir(graph, options)) {
    impl_.derived.nextGeneration();
  }

  EvalReport evaluate() {
    if (!plan()) return std::move(report_);
    retireUnreachable();
    queuePreparations();
    evaluateNodes();
    // Preparations under way for nodes this run did not reach (an input failed) end here.
    for (auto& [name, preparation] : preparations_)
      preparation.finish();
    orderRuns();
    commitFiles();
    retire();
    return std::move(report_);
  }

 private:
  // The order, the keys and the nodes needed; false (the report says why) where the graph
  // cannot be evaluated.
  bool plan() {
    try {
      order_ = topologicalOrder(graph_);
      keys_ = evaluator_.nodeKeys(graph_, options_);
      checkOutputPaths(graph_, impl_.registry, outputDir_);
    } catch (const GraphError& e) {
      fail(report_, e);
      return false;
    } catch (const std::exception& e) {
      report_.ok = false;
      report_.error = e.what();
      return false;
    }
    sources_ = indexSources(graph_);
    return selectNeeded();
  }

  // Pull: only the targets and what they depend on.
  bool selectNeeded() {
    if (options_.targets.empty()) {
      needed_.insert(order_.begin(), order_.end());
      return true;
    }
    std::vector<std::string> stack = options_.targets;
    while (!stack.empty()) {
      std::string name = stack.back();
      stack.pop_back();
      if (!graph_.nodes.count(name)) {
        fail(report_, GraphError(graph_.file, name, "", "no node of that name to evaluate"));
        return false;
      }
      if (!needed_.insert(name).second) continue;
      for (auto it = sources_.lower_bound({name, ""});
           it != sources_.end() && it->first.first == name; ++it)
        stack.push_back(it->second.node);
    }
    return true;
  }

  const NodeType& typeOf(const std::string& name) const {
    return *impl_.registry.find(graph_.nodes.at(name).type);
  }

  // The cached result under `key`, or none; with `settle`, a result that depends on a node's
  // history is none.
  Entry* cached(Hash key) {
    auto hit = impl_.cache.find(key);
    if (hit == impl_.cache.end() || (options_.settle && hit->second.history)) return nullptr;
    return &hit->second;
  }

  // The key of the value on each connected input port among `ports`: its node's key and port.
  InputKeys inputKeysOf(const std::string& name, const std::vector<std::string>& ports) const {
    InputKeys inputKeys;
    for (const auto& port : ports)
      if (const Endpoint* from = findSource(sources_, name, port))
        inputKeys[port] = Hasher().u64(keys_.at(from->node)).str(from->port).digest();
    return inputKeys;
  }

  // Nodes that prepare (Node::prepare): each starts on another thread once the inputs it
  // prepares from are ready while another of its inputs is not, so that it overlaps that input's
  // computation; otherwise it runs just before the node's compute(). The outputs are the same.
  void queuePreparations() {
    for (const auto& name : order_)
      if (needed_.count(name) && !typeOf(name).prepareInputs.empty() && !cached(keys_.at(name)))
        waiting_.push_back(name);
  }

  Preparation& startPreparation(const std::string& name, bool ahead) {
    const auto& [stableName, node] = *graph_.nodes.find(name);
    const NodeType& type = typeOf(name);
    Preparation& preparation = preparations_[stableName];
    for (const auto& port : type.prepareInputs)
      if (const Endpoint* from = findSource(sources_, stableName, port))
        preparation.inputs[port] = results_.at(from->node).at(from->port);
    preparation.context = std::make_unique<EvalContext>(
        type, node, stableName, preparation.inputs, inputKeysOf(stableName, type.prepareInputs),
        impl_.derived, impl_.bin, impl_.binMutex, baseDir_, outputDir_, options_, true);
    Node& instance = impl_.instance(stableName, type, options_.settle);
    if (ahead) {
      try {
        preparation.running = std::async(std::launch::async,
                                         [&preparation, &instance] { preparation.run(instance); });
        return preparation;
      } catch (const std::system_error&) {
        // No thread to spare: it runs here.
      }
    }
    preparation.run(instance);
    return preparation;
  }

  void startReadyPreparations() {
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      const NodeType& type = typeOf(*it);
      bool prepareReady = true, otherPending = false;
      for (const auto& port : type.inputs) {
        const Endpoint* from = findSource(sources_, *it, port.name);
        if (!from) continue;
        const bool ready = results_.count(from->node) > 0;
        const auto& prepares = type.prepareInputs;
        if (std::find(prepares.begin(), prepares.end(), port.name) != prepares.end())
          prepareReady = prepareReady && ready;
        else
          otherPending = otherPending || !ready;
      }
      if (prepareReady && otherPending) {
        startPreparation(*it, true);
        it = waiting_.erase(it);
      } else {
        ++it;
      }
    }
  }

  // The needed nodes in order, each once its inputs are there. Nodes ready beside the next one
  // (independent branches) compute at the same time on other threads; what the run reports,
  // caches and stops at is what evaluating them one at a time gives.
  void evaluateNodes() {
    std::vector<std::string> pending;
    for (const auto& name : order_)
      if (needed_.count(name)) pending.push_back(name);
    for (std::size_t next = 0; next < pending.size(); ++next) {
      const std::string& name = pending[next];
      if (results_.count(name)) continue;  // computed beside an earlier one
      if (auto failed = failedAhead_.find(name); failed != failedAhead_.end()) {
        report_.runs.push_back(failed->second.run);
        fail(report_, graph_, name, failed->second.failure);
        return;
      }
      startReadyPreparations();
      const std::vector<std::string> beside = besideOf(pending, next);
      if (!(beside.empty() ? evaluateNode(name) : computeTogether(name, beside))) return;
    }
  }

  // A node computes on another thread where it would compute anyway (no cached result) and has
  // no preparation of its own to interleave.
  bool computesAnywhere(const std::string& name) {
    return !cached(keys_.at(name)) && typeOf(name).prepareInputs.empty();
  }

  bool inputsReady(const std::string& name) const {
    for (auto it = sources_.lower_bound({name, ""});
         it != sources_.end() && it->first.first == name; ++it)
      if (!results_.count(it->second.node)) return false;
    return true;
  }

  // The nodes after pending[next] that can compute beside it now, one per spare core.
  std::vector<std::string> besideOf(const std::vector<std::string>& pending, std::size_t next) {
    std::vector<std::string> beside;
    if (!computesAnywhere(pending[next])) return beside;
    const std::size_t width = std::max(2u, std::thread::hardware_concurrency());
    std::set<Hash> keys = {keys_.at(pending[next])};
    for (std::size_t k = next + 1; k < pending.size() && beside.size() + 1 < width; ++k) {
      const std::string& name = pending[k];
      // A node of a key already computing would be a cache hit one at a time: it waits.
      if (results_.count(name) || failedAhead_.count(name) || !inputsReady(name) ||
          !computesAnywhere(name) || !keys.insert(keys_.at(name)).second)
        continue;
      beside.push_back(name);
    }
    return beside;
  }

  // One node: its cached result, or its computation. False where it failed: the run stops.
  bool evaluateNode(const std::string& name) {
    NodeRun run;
    run.node = name;
    run.type = typeOf(name).id;
    run.key = keys_.at(name);
    const bool ok =
        cached(run.key) ? reuseCached(name, run, *cached(run.key)) : computeNode(name, run);
    report_.runs.push_back(std::move(run));
    return ok;
  }

  bool reuseCached(const std::string& name, NodeRun& run, Entry& entry) {
    // A node of the same key computed earlier in this run: a preparation started for this one
    // is not needed.
    if (auto prepared = preparations_.find(name); prepared != preparations_.end())
      prepared->second.finish();
    entry.lastUsed = generation_;
    run.cacheHit = true;
    run.history = history_[name] = entry.history;
    run.warnings = entry.warnings;
    if (entry.failure) {
      run.failed = true;
      fail(report_, graph_, name, *entry.failure);
      return false;
    }
    results_[name] = entry.outputs;
    return true;
  }

  // A node's computation: set up and finished on the evaluating thread, run on any.
  struct Computation {
    std::string name;
    NodeRun run;
    Outputs inputs;
    std::unique_ptr<EvalContext> ctx;
    Node* instance = nullptr;
    bool inputHistory = false;
    std::optional<Failure> failure;
    bool cancelled = false;
    double preparedSeconds = 0;
    std::atomic<double> progress{-1.0};  // relayed from another thread
  };

  bool computeNode(const std::string& name, NodeRun& run) {
    Computation computation;
    computation.run = std::move(run);
    startComputation(name, computation);
    runComputation(computation);
    const bool ok = finishComputation(computation);
    run = std::move(computation.run);
    if (!ok) fail(report_, graph_, name, *computation.failure);
    return ok;
  }

  // `first` on this thread and `beside` on others, their results taken in order; a failure
  // beside waits until the run reaches its node. The others' progress is reported from here.
  bool computeTogether(const std::string& first, const std::vector<std::string>& beside) {
    std::vector<std::unique_ptr<Computation>> work;
    work.push_back(std::make_unique<Computation>());
    startComputation(first, *work.back());
    for (const auto& name : beside) {
      work.push_back(std::make_unique<Computation>());
      startComputation(name, *work.back());
      work.back()->ctx->relayProgressThrough(&work.back()->progress);
    }
    std::vector<std::future<void>> running(work.size());
    for (std::size_t i = 1; i < work.size(); ++i) {
      try {
        running[i] =
            std::async(std::launch::async, [this, c = work[i].get()] { runComputation(*c); });
      } catch (const std::system_error&) {
        // No thread to spare: it runs here, after the first.
      }
    }
    // Each node's progress runs from its start to its end before the next one's.
    runComputation(*work[0]);
    const bool ok = takeResult(*work[0], true);
    for (std::size_t i = 1; i < work.size(); ++i) {
      const bool ranBeside = running[i].valid();
      if (ranBeside) relayProgressUntilDone(*work[i], running[i]);
      work[i]->ctx->relayProgressThrough(nullptr);
      if (!ranBeside) runComputation(*work[i]);
      takeResult(*work[i], false);
    }
    return ok;
  }

  // A computation's results; a failure is reported now for the `first` node, else when the run
  // reaches its node.
  bool takeResult(Computation& c, bool first) {
    if (finishComputation(c)) {
      report_.runs.push_back(std::move(c.run));
      return true;
    }
    if (first) {
      report_.runs.push_back(c.run);
      fail(report_, graph_, c.name, *c.failure);
    } else {
      failedAhead_.emplace(c.name, FailedAhead{std::move(c.run), *c.failure});
    }
    return false;
  }

  void relayProgressUntilDone(Computation& c, std::future<void>& running) {
    double reported = -1.0;
    // From its start (0), however far the node has come when this thread gets to it.
    const auto relay = [&] {
      const double fraction = c.progress.load(std::memory_order_relaxed);
      if (fraction < 0.0 || !options_.progress) return;
      if (reported < 0.0) options_.progress(c.name, reported = 0.0);
      if (fraction != reported) options_.progress(c.name, reported = fraction);
    };
    while (running.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready)
      relay();
    relay();
    running.get();
  }

  // The runs in evaluation order, as one node at a time gives them: none after a failed one, and
  // no outputs from a node after it that computed beside an earlier one.
  void orderRuns() {
    std::map<std::string, std::size_t> position;
    for (std::size_t i = 0; i < order_.size(); ++i)
      position[order_[i]] = i;
    auto& runs = report_.runs;
    std::stable_sort(runs.begin(), runs.end(), [&](const NodeRun& a, const NodeRun& b) {
      return position.at(a.node) < position.at(b.node);
    });
    const auto failed =
        std::find_if(runs.begin(), runs.end(), [](const NodeRun& run) { return run.failed; });
    if (failed == runs.end()) return;
    const std::size_t stop = position.at(failed->node);
    runs.erase(std::next(failed), runs.end());
    std::erase_if(results_, [&](const auto& result) { return position.at(result.first) > stop; });
  }

  // The inputs, the context, the preparation (run ahead, or now) and the node instance.
  void startComputation(const std::string& name, Computation& c) {
    const auto& [stableName, node] = *graph_.nodes.find(name);
    const NodeType& type = typeOf(name);
    c.name = stableName;
    c.run.node = stableName;
    c.run.type = type.id;
    c.run.key = keys_.at(name);
    for (const auto& port : type.inputs)
      if (const Endpoint* from = findSource(sources_, name, port.name)) {
        c.inputs[port.name] = results_.at(from->node).at(from->port);
        c.inputHistory = c.inputHistory || history_[from->node];
      }
    c.ctx = std::make_unique<EvalContext>(
        type, node, stableName, c.inputs, inputKeysOf(name, inputNames(type)), impl_.derived,
        impl_.bin, impl_.binMutex, baseDir_, outputDir_, options_);
    const bool prepared = !type.prepareInputs.empty();
    if (prepared) {
      auto found = preparations_.find(name);
      Preparation& preparation =
          found != preparations_.end() ? found->second : startPreparation(name, false);
      std::erase(waiting_, name);
      preparation.finish();
      c.failure = preparation.failure;
      c.cancelled = preparation.cancelled;
      c.preparedSeconds = preparation.seconds;
      c.run.warnings = preparation.context->warnings();
    }
    ++evaluator_.computeCount_;
    if (c.failure) return;
    // A prepared node computes on the instance that prepared.
    bool cancelled = false;
    c.failure = guarded(
        [&] { c.instance = &impl_.instance(name, type, options_.settle && !prepared); }, cancelled);
  }

  // compute(), on any thread.
  void runComputation(Computation& c) const {
    const auto start = std::chrono::steady_clock::now();
    if (!c.failure) {
      const NodeType& type = typeOf(c.name);
      EvalContext& ctx = *c.ctx;
      bool cancelled = false;
      c.failure = guarded(
          [&] {
            ctx.throwIfCancelled();
            ctx.progress(0.0);
            c.instance->compute(ctx);
            c.run.history = c.instance->usedHistory() || c.inputHistory;
            for (const auto& port : type.outputs)
              if (!ctx.outputs().count(port.name))
                throw NodeError::output(port.name, "was not set by '" + type.id + "'");
          },
          cancelled);
      c.cancelled = c.cancelled || cancelled;
    }
    c.run.seconds = c.preparedSeconds +
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // What the computation leaves: warnings, files, the cache entry and the outputs. False where
  // it failed (the caller reports it).
  bool finishComputation(Computation& c) {
    EvalContext& ctx = *c.ctx;
    report_.cancelled = report_.cancelled || c.cancelled;
    c.run.warnings.insert(c.run.warnings.end(), ctx.warnings().begin(), ctx.warnings().end());
    for (auto& file : ctx.pending())
      pendingFiles_.push_back(file);
    if (c.failure) {
      c.run.failed = true;
      // Deterministic failures are remembered; a cancelled run is not a result.
      if (!c.cancelled && !report_.cancelled && ctx.pending().empty())
        impl_.cache[c.run.key] = {{}, c.failure, c.run.warnings, generation_, false, c.name, {}};
      return false;
    }
    ctx.progress(1.0);
    history_[c.name] = c.run.history;
    Entry entry{ctx.outputs(),
                std::nullopt,
                c.run.warnings,
                generation_,
                c.run.history,
                c.name,
                std::move(ctx.recyclable())};
    results_[c.name] = ctx.outputs();
    if (ctx.pending().empty())
      impl_.cache[c.run.key] = std::move(entry);
    else
      deferredEntries_.emplace_back(c.run.key, std::move(entry));
    return true;
  }

  // The files of the run appear all together, or none of them; file writers' results are
  // cached once theirs are in place.
  void commitFiles() {
    if (report_.ok) {
      for (const auto& file : pendingFiles_) {
        try {
          replaceWithTemporary(file.tmp, file.target);
        } catch (const std::runtime_error& e) {
          fail(report_, GraphError(graph_.file, file.node, "", e.what()));
          break;
        }
        report_.filesWritten.push_back(file.target);
      }
    }
    std::error_code ec;
    if (!report_.ok) {
      for (const auto& file : pendingFiles_)
        std::filesystem::remove(file.tmp, ec);
    } else {
      for (auto& [key, entry] : deferredEntries_)
        impl_.cache[key] = std::move(entry);
    }
  }

  // Keep what this run or the previous one used: toggling a param back and forth stays
  // instant, and memory stays bounded by two graphs' worth. What a retired entry published as
  // recyclable goes to the bin, for its node to build a later result in.
  void retire() {
    retireEntries([&](Hash, const Entry& entry) { return entry.lastUsed + 1 < generation_; });
    for (auto it = impl_.instances.begin(); it != impl_.instances.end();)
      it = graph_.nodes.count(it->first) ? std::next(it) : impl_.instances.erase(it);
    std::set<std::string> nodes;
    for (const auto& [name, node] : graph_.nodes)
      nodes.insert(name);
    impl_.bin.keepNodes(nodes);
    impl_.lastOutputs = std::move(results_);
  }

  // The entries retire() drops at the end of this run that no node of it can hit (their keys are
  // not this run's), dropped before it computes: a result made two runs back is then in the bin
  // for this run's nodes to build in, and does not sit beside the results they make.
  void retireUnreachable() {
    std::set<Hash> keys;
    for (const auto& [name, key] : keys_)
      keys.insert(key);
    retireEntries([&](Hash key, const Entry& entry) {
      return entry.lastUsed + 1 < generation_ && !keys.count(key);
    });
  }

  template <typename Drop>
  void retireEntries(const Drop& drop) {
    for (auto it = impl_.cache.begin(); it != impl_.cache.end();) {
      if (!drop(it->first, it->second)) {
        ++it;
        continue;
      }
      for (auto& [port, value] : it->second.recyclable)
        impl_.bin.put(it->second.node, port, std::move(value));
      it = impl_.cache.erase(it);
    }
  }

  Evaluator& evaluator_;
  Impl& impl_;
  const Graph& graph_;
  const EvalOptions& options_;
  const std::uint64_t generation_;
  const std::filesystem::path baseDir_, outputDir_;
  EvalReport report_;
  std::vector<std::string> order_;  // every node, upstream first
  std::map<std::string, Hash> keys_;
  SourceIndex sources_;
  std::set<std::string> needed_;  // the targets and what they depend on
  std::map<std::string, Outputs> results_;
  std::map<std::string, bool> history_;  // per node evaluated: NodeRun::history
  std::vector<PendingFile> pendingFiles_;
  std::vector<std::pair<Hash, Entry>> deferredEntries_;  // file writers: cached after commit
  std::map<std::string, Preparation> preparations_;
  std::vector<std::string> waiting_;  // preparing nodes not started yet, in evaluation order
  // Nodes that failed computing beside an earlier one, reported when the run reaches them.
  struct FailedAhead {
    NodeRun run;
    Failure failure;
  };
  std::map<std::string, FailedAhead> failedAhead_;
};

Evaluator::Evaluator(const NodeRegistry& registry) : impl_(std::make_unique<Impl>(registry)) {}
Evaluator::~Evaluator() = default;

std::size_t Evaluator::recycledHeld() const {
  return impl_->bin.size();
}

void Evaluator::clearCache() {
  impl_->cache.clear();
  impl_->instances.clear();
  impl_->derived.clear();
  impl_->bin.clear();
}

std::uint64_t Evaluator::derivedBuildCount() const {
  return impl_->derived.builds();
}

std::size_t Evaluator::derivedHeld() const {
  return impl_->derived.size();
}

ValuePtr Evaluator::output(const std::string& node, const std::string& port) const {
  auto it = impl_->lastOutputs.find(node);
  if (it == impl_->lastOutputs.end()) return nullptr;
  auto value = it->second.find(port);
  return value == it->second.end() ? nullptr : value->second;
}

std::map<std::string, Hash> Evaluator::nodeKeys(const Graph& graph,
                                                const EvalOptions& options) const {
  const auto baseDir = graph.baseDir();
  const auto outputDir = impl_->outputDir(graph, options);
  const SourceIndex sources = indexSources(graph);
  std::map<std::string, Hash> keys;
  for (const auto& name : topologicalOrder(graph)) {
    const GraphNode& node = graph.nodes.at(name);
    const NodeType* type = impl_->registry.find(node.type);
    if (!type) throw GraphError(graph.file, name, "", "unknown node type '" + node.type + "'");
    Hasher hasher;
    hasher.str(type->id).u64(std::uint64_t(type->version));
    for (const auto& decl : type->params) {
      const ParamValue& value = effectiveParam(node, decl);
      hasher.str(decl.name);
      hashParam(hasher, value);
      if (decl.kind == ParamKind::InputPath) {
        const auto path = resolvePath(std::get<std::string>(value), baseDir);
        hasher.str(path.string());
        hashFileState(hasher, path);
      } else if (decl.kind == ParamKind::OutputPath) {
        hasher.str(resolvePath(std::get<std::string>(value), outputDir).string());
      }
    }
    for (const auto& port : type->inputs) {
      hasher.str(port.name);
      if (const Endpoint* from = findSource(sources, name, port.name))
        hasher.u64(keys.at(from->node)).str(from->port);
      else
        hasher.u64(0);
    }
    keys[name] = hasher.digest();
  }
  return keys;
}

EvalReport Evaluator::evaluate(const Graph& graph, const EvalOptions& options) {
  return Impl::Run(*this, graph, options).evaluate();
}

CollectedMetrics collectMetrics(const Graph& graph, const NodeRegistry& registry,
                                const Evaluator& evaluator) {
  CollectedMetrics collected;
  for (const auto& [name, node] : graph.nodes) {
    const NodeType* type = registry.find(node.type);
    if (!type) continue;
    for (const auto& port : type->outputs) {
      const auto metrics =
          std::dynamic_pointer_cast<const Metrics>(evaluator.output(name, port.name));
      if (!metrics) continue;
      for (const auto& [key, value] : metrics->values)
        collected.values[name + "." + key] = value;
      for (const auto& note : metrics->notes)
        collected.notes.push_back(name + ": " + note);
    }
  }
  return collected;
}

}  // namespace geobrush
