#include "geobrush/evaluator.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <future>
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
              const Outputs& inputs, InputKeys inputKeys, DerivedStore& derived,
              const std::filesystem::path& baseDir, const std::filesystem::path& outputDir,
              const EvalOptions& options, bool preparing = false)
      : type_(type),
        node_(node),
        name_(name),
        inputs_(inputs),
        inputKeys_(std::move(inputKeys)),
        derived_(derived),
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

 private:
  const NodeType& type_;
  const GraphNode& node_;
  const std::string& name_;
  const Outputs& inputs_;
  InputKeys inputKeys_;
  DerivedStore& derived_;
  std::filesystem::path baseDir_;
  std::filesystem::path outputDir_;
  const EvalOptions& options_;
  bool preparing_ = false;
  Outputs outputs_;
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
  };
  struct Instance {
    const NodeType* type = nullptr;
    std::unique_ptr<Node> node;
  };

  const NodeRegistry& registry;
  std::unordered_map<Hash, Entry> cache;
  std::map<std::string, Instance> instances;
  std::map<std::string, Outputs> lastOutputs;
  DerivedStore derived;
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

Evaluator::Evaluator(const NodeRegistry& registry) : impl_(std::make_unique<Impl>(registry)) {}
Evaluator::~Evaluator() = default;

void Evaluator::clearCache() {
  impl_->cache.clear();
  impl_->instances.clear();
  impl_->derived.clear();
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
  EvalReport report;
  Impl& impl = *impl_;
  const std::uint64_t generation = ++impl.generation;
  impl.derived.nextGeneration();

  std::map<std::string, Hash> keys;
  std::vector<std::string> order;
  try {
    order = topologicalOrder(graph);
    keys = nodeKeys(graph, options);
    checkOutputPaths(graph, impl.registry, impl.outputDir(graph, options));
  } catch (const GraphError& e) {
    fail(report, e);
    return report;
  } catch (const std::exception& e) {
    report.ok = false;
    report.error = e.what();
    return report;
  }

  // Pull: only the targets and what they depend on.
  const SourceIndex sources = indexSources(graph);
  std::set<std::string> needed;
  if (options.targets.empty()) {
    needed.insert(order.begin(), order.end());
  } else {
    std::vector<std::string> stack = options.targets;
    while (!stack.empty()) {
      std::string name = stack.back();
      stack.pop_back();
      if (!graph.nodes.count(name)) {
        fail(report, GraphError(graph.file, name, "", "no node of that name to evaluate"));
        return report;
      }
      if (!needed.insert(name).second) continue;
      for (auto it = sources.lower_bound({name, ""});
           it != sources.end() && it->first.first == name; ++it)
        stack.push_back(it->second.node);
    }
  }

  const auto baseDir = graph.baseDir();
  const auto outputDir = impl.outputDir(graph, options);
  std::map<std::string, Outputs> results;
  std::map<std::string, bool> history;  // per node evaluated: NodeRun::history
  std::vector<PendingFile> pendingFiles;
  std::vector<std::pair<Hash, Impl::Entry>> deferredEntries;  // file writers: cached after commit

  // Nodes that prepare (Node::prepare): each starts on another thread once the inputs it prepares
  // from are ready while another of its inputs is not, so that it overlaps that input's
  // computation; otherwise it runs just before the node's compute(). The outputs are the same.
  auto cacheHit = [&](Hash key) {
    auto hit = impl.cache.find(key);
    return hit != impl.cache.end() && !(options.settle && hit->second.history);
  };
  // The key of the value on each connected input port among `ports`: its node's key and port.
  auto inputKeysOf = [&](const std::string& name, const std::vector<std::string>& ports) {
    InputKeys inputKeys;
    for (const auto& port : ports)
      if (const Endpoint* from = findSource(sources, name, port))
        inputKeys[port] = Hasher().u64(keys.at(from->node)).str(from->port).digest();
    return inputKeys;
  };
  std::map<std::string, Preparation> preparations;
  std::vector<std::string> waiting;  // preparing nodes not started yet, in evaluation order
  for (const auto& name : order) {
    if (!needed.count(name)) continue;
    if (!impl.registry.find(graph.nodes.at(name).type)->prepareInputs.empty() &&
        !cacheHit(keys.at(name)))
      waiting.push_back(name);
  }
  auto startPreparation = [&](const std::string& name, bool ahead) -> Preparation& {
    const auto& [stableName, node] = *graph.nodes.find(name);
    const NodeType& type = *impl.registry.find(node.type);
    Preparation& preparation = preparations[stableName];
    for (const auto& port : type.prepareInputs)
      if (const Endpoint* from = findSource(sources, stableName, port))
        preparation.inputs[port] = results.at(from->node).at(from->port);
    preparation.context = std::make_unique<EvalContext>(
        type, node, stableName, preparation.inputs, inputKeysOf(stableName, type.prepareInputs),
        impl.derived, baseDir, outputDir, options, true);
    Node& instance = impl.instance(stableName, type, options.settle);
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
  };
  auto startReadyPreparations = [&] {
    for (auto it = waiting.begin(); it != waiting.end();) {
      const NodeType& type = *impl.registry.find(graph.nodes.at(*it).type);
      bool prepareReady = true, otherPending = false;
      for (const auto& port : type.inputs) {
        const Endpoint* from = findSource(sources, *it, port.name);
        if (!from) continue;
        const bool ready = results.count(from->node) > 0;
        const auto& prepares = type.prepareInputs;
        if (std::find(prepares.begin(), prepares.end(), port.name) != prepares.end())
          prepareReady = prepareReady && ready;
        else
          otherPending = otherPending || !ready;
      }
      if (prepareReady && otherPending) {
        startPreparation(*it, true);
        it = waiting.erase(it);
      } else {
        ++it;
      }
    }
  };

  for (const auto& name : order) {
    if (!needed.count(name)) continue;
    startReadyPreparations();
    const GraphNode& node = graph.nodes.at(name);
    const NodeType& type = *impl.registry.find(node.type);
    const Hash key = keys.at(name);
    NodeRun run;
    run.node = name;
    run.type = type.id;
    run.key = key;

    Outputs inputs;
    bool inputHistory = false;
    for (const auto& port : type.inputs)
      if (const Endpoint* from = findSource(sources, name, port.name)) {
        inputs[port.name] = results[from->node].at(from->port);
        inputHistory = inputHistory || history[from->node];
      }

    auto hit = impl.cache.find(key);
    if (hit != impl.cache.end() && options.settle && hit->second.history) hit = impl.cache.end();
    if (hit != impl.cache.end()) {
      // A node of the same key computed earlier in this run: a preparation started for this one
      // is not needed.
      if (auto prepared = preparations.find(name); prepared != preparations.end())
        prepared->second.finish();
      hit->second.lastUsed = generation;
      run.cacheHit = true;
      run.history = history[name] = hit->second.history;
      run.warnings = hit->second.warnings;
      if (hit->second.failure) {
        run.failed = true;
        fail(report, graph, name, *hit->second.failure);
        report.runs.push_back(std::move(run));
        break;
      }
      results[name] = hit->second.outputs;
      report.runs.push_back(std::move(run));
      continue;
    }

    EvalContext ctx(type, node, name, inputs, inputKeysOf(name, inputNames(type)), impl.derived,
                    baseDir, outputDir, options);
    std::optional<Failure> failure;
    double preparedSeconds = 0;
    bool prepared = false;
    if (!type.prepareInputs.empty()) {
      auto found = preparations.find(name);
      Preparation& preparation =
          found != preparations.end() ? found->second : startPreparation(name, false);
      std::erase(waiting, name);
      preparation.finish();
      failure = preparation.failure;
      report.cancelled = report.cancelled || preparation.cancelled;
      preparedSeconds = preparation.seconds;
      run.warnings = preparation.context->warnings();
      prepared = true;
    }
    const auto start = std::chrono::steady_clock::now();
    ++computeCount_;
    if (!failure) {
      bool cancelled = false;
      failure = guarded(
          [&] {
            ctx.throwIfCancelled();
            ctx.progress(0.0);
            // A prepared node computes on the instance that prepared.
            Node& instance = impl.instance(name, type, options.settle && !prepared);
            instance.compute(ctx);
            run.history = instance.usedHistory() || inputHistory;
            for (const auto& port : type.outputs)
              if (!ctx.outputs().count(port.name))
                throw NodeError::output(port.name, "was not set by '" + type.id + "'");
          },
          cancelled);
      report.cancelled = report.cancelled || cancelled;
    }
    run.seconds = preparedSeconds +
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.warnings.insert(run.warnings.end(), ctx.warnings().begin(), ctx.warnings().end());
    for (auto& file : ctx.pending())
      pendingFiles.push_back(file);

    if (failure) {
      run.failed = true;
      fail(report, graph, name, *failure);
      // Deterministic failures are remembered; a cancelled run is not a result.
      if (!report.cancelled && ctx.pending().empty())
        impl.cache[key] = {{}, failure, run.warnings, generation};
      report.runs.push_back(std::move(run));
      break;
    }
    ctx.progress(1.0);
    history[name] = run.history;
    Impl::Entry entry{ctx.outputs(), std::nullopt, run.warnings, generation, run.history};
    results[name] = ctx.outputs();
    if (ctx.pending().empty())
      impl.cache[key] = std::move(entry);
    else
      deferredEntries.emplace_back(key, std::move(entry));
    report.runs.push_back(std::move(run));
  }

  // Preparations under way for nodes this run did not reach (an input failed) end here.
  for (auto& [name, preparation] : preparations)
    preparation.finish();

  // The files of the run appear all together, or none of them.
  std::error_code ec;
  if (report.ok) {
    for (const auto& file : pendingFiles) {
      try {
        replaceWithTemporary(file.tmp, file.target);
      } catch (const std::runtime_error& e) {
        fail(report, GraphError(graph.file, file.node, "", e.what()));
        break;
      }
      report.filesWritten.push_back(file.target);
    }
  }
  if (!report.ok) {
    for (const auto& file : pendingFiles)
      std::filesystem::remove(file.tmp, ec);
  } else {
    for (auto& [key, entry] : deferredEntries)
      impl.cache[key] = std::move(entry);
  }

  // Keep what this run or the previous one used: toggling a param back and
  // forth stays instant, and memory stays bounded by two graphs' worth.
  std::erase_if(impl.cache,
                [&](const auto& item) { return item.second.lastUsed + 1 < generation; });
  for (auto it = impl.instances.begin(); it != impl.instances.end();)
    it = graph.nodes.count(it->first) ? std::next(it) : impl.instances.erase(it);
  impl.lastOutputs = std::move(results);
  return report;
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
