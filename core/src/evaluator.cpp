#include "geobrush/evaluator.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <mutex>
#include <optional>
#include <set>
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
    if (options_.progress && !preparing_) options_.progress(name_, std::clamp(fraction, 0.0, 1.0));
  }
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
  std::mutex& binMutex_;  // a preparation running ahead shares the bin with computes
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
    queuePreparations();
    for (const auto& name : order_)
      if (needed_.count(name) && !evaluateNode(name)) break;
    // Preparations under way for nodes this run did not reach (an input failed) end here.
    for (auto& [name, preparation] : preparations_)
      preparation.finish();
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

  // One node: its cached result, or its computation. False where it failed: the run stops.
  bool evaluateNode(const std::string& name) {
    startReadyPreparations();
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

  // The node's prepare() (run ahead, or now), then its compute().
  bool computeNode(const std::string& name, NodeRun& run) {
    const GraphNode& node = graph_.nodes.at(name);
    const NodeType& type = typeOf(name);
    Outputs inputs;
    bool inputHistory = false;
    for (const auto& port : type.inputs)
      if (const Endpoint* from = findSource(sources_, name, port.name)) {
        inputs[port.name] = results_[from->node].at(from->port);
        inputHistory = inputHistory || history_[from->node];
      }
    EvalContext ctx(type, node, name, inputs, inputKeysOf(name, inputNames(type)), impl_.derived,
                    impl_.bin, impl_.binMutex, baseDir_, outputDir_, options_);
    std::optional<Failure> failure;
    double preparedSeconds = 0;
    const bool prepared = !type.prepareInputs.empty();
    if (prepared) {
      auto found = preparations_.find(name);
      Preparation& preparation =
          found != preparations_.end() ? found->second : startPreparation(name, false);
      std::erase(waiting_, name);
      preparation.finish();
      failure = preparation.failure;
      report_.cancelled = report_.cancelled || preparation.cancelled;
      preparedSeconds = preparation.seconds;
      run.warnings = preparation.context->warnings();
    }
    const auto start = std::chrono::steady_clock::now();
    ++evaluator_.computeCount_;
    if (!failure) {
      bool cancelled = false;
      failure = guarded(
          [&] {
            ctx.throwIfCancelled();
            ctx.progress(0.0);
            // A prepared node computes on the instance that prepared.
            Node& instance = impl_.instance(name, type, options_.settle && !prepared);
            instance.compute(ctx);
            run.history = instance.usedHistory() || inputHistory;
            for (const auto& port : type.outputs)
              if (!ctx.outputs().count(port.name))
                throw NodeError::output(port.name, "was not set by '" + type.id + "'");
          },
          cancelled);
      report_.cancelled = report_.cancelled || cancelled;
    }
    run.seconds = preparedSeconds +
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.warnings.insert(run.warnings.end(), ctx.warnings().begin(), ctx.warnings().end());
    for (auto& file : ctx.pending())
      pendingFiles_.push_back(file);
    if (failure) {
      run.failed = true;
      fail(report_, graph_, name, *failure);
      // Deterministic failures are remembered; a cancelled run is not a result.
      if (!report_.cancelled && ctx.pending().empty())
        impl_.cache[run.key] = {{}, failure, run.warnings, generation_, false, name, {}};
      return false;
    }
    ctx.progress(1.0);
    history_[name] = run.history;
    Entry entry{ctx.outputs(),
                std::nullopt,
                run.warnings,
                generation_,
                run.history,
                name,
                std::move(ctx.recyclable())};
    results_[name] = ctx.outputs();
    if (ctx.pending().empty())
      impl_.cache[run.key] = std::move(entry);
    else
      deferredEntries_.emplace_back(run.key, std::move(entry));
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
    for (auto it = impl_.cache.begin(); it != impl_.cache.end();) {
      if (it->second.lastUsed + 1 >= generation_) {
        ++it;
        continue;
      }
      for (auto& [port, value] : it->second.recyclable)
        impl_.bin.put(it->second.node, port, std::move(value));
      it = impl_.cache.erase(it);
    }
    for (auto it = impl_.instances.begin(); it != impl_.instances.end();)
      it = graph_.nodes.count(it->first) ? std::next(it) : impl_.instances.erase(it);
    std::set<std::string> nodes;
    for (const auto& [name, node] : graph_.nodes)
      nodes.insert(name);
    impl_.bin.keepNodes(nodes);
    impl_.lastOutputs = std::move(results_);
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
