#include "commands.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/text.hpp"
#include "geobrush/values.hpp"

namespace geobrush::cli {

void printError(const std::string& message) {
  std::fprintf(stderr, "error: %s\n", messageLine(message).c_str());
}

void printWarning(const std::string& message) {
  std::fprintf(stderr, "warning: %s\n", messageLine(message).c_str());
}

std::vector<std::string> loadPlugins(NodeRegistry& registry, bool quiet) {
  auto report = registry.loadPlugins(defaultPluginDirs());
  if (!quiet)
    for (const auto& error : report.errors)
      printWarning(error);
  return report.errors;
}

namespace {

// Each computed node's progress on stderr: one status line rewritten in place on a terminal
// ("[2] gdem 40%"), or, for logs, a line when a node starts, at each tenth done and when it ends,
// with its time.
class ProgressPrinter {
 public:
  enum class Mode { Off, Terminal, Lines };
  explicit ProgressPrinter(Mode mode) : mode_(mode) {}
  ~ProgressPrinter() { clear(); }

  void update(const std::string& node, double fraction) {
    if (mode_ == Mode::Off) return;
    const bool started = node != node_;
    if (started) {
      node_ = node;
      ++index_;
      tenths_ = -1;
      start_ = std::chrono::steady_clock::now();
    }
    const int percent = int(fraction * 100 + 0.5);
    if (mode_ == Mode::Terminal) {
      if (!started && percent == percent_) return;
      percent_ = percent;
      std::fprintf(stderr, "\r\033[K[%d] %s %3d%%", index_, escapeText(node).c_str(), percent);
      dirty_ = true;
    } else if (const int tenths = int(fraction * 10); tenths > tenths_) {
      tenths_ = tenths;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      std::fprintf(stderr, "progress: [%d] %s %d%% %.2f s\n", index_, escapeText(node).c_str(),
                   percent, seconds);
    }
    std::fflush(stderr);
  }
  void clear() {
    if (!dirty_) return;
    std::fprintf(stderr, "\r\033[K");
    dirty_ = false;
  }

 private:
  Mode mode_;
  bool dirty_ = false;
  int index_ = 0;
  int tenths_ = -1;
  int percent_ = -1;
  std::string node_;
  std::chrono::steady_clock::time_point start_;
};

ProgressPrinter::Mode progressMode(const ReportOptions& options) {
  if (options.progressLines) return ProgressPrinter::Mode::Lines;
  if (options.quiet || !::isatty(STDERR_FILENO)) return ProgressPrinter::Mode::Off;
  return ProgressPrinter::Mode::Terminal;
}

}  // namespace

int runGraph(const RunOptions& options) {
  NodeRegistry registry;
  const auto pluginErrors = loadPlugins(registry, options.quiet || options.json);
  Graph graph;
  try {
    graph = readGraphFile(options.graph);
    prepareGraph(graph, registry);
    for (const auto& assignment : options.sets)
      setParamFromText(graph, registry, assignment);
    // Now that --set and --out are known: two outputs to one file are a graph error, before
    // anything runs.
    checkOutputPaths(
        graph, registry,
        options.outDir.empty() ? graph.baseDir() : std::filesystem::absolute(options.outDir));
  } catch (const GraphError& e) {
    printError(e.what());
    if (options.json) {
      EvalReport failed;
      failed.ok = false;
      failed.error = e.what();
      std::cout << runReportJson(options.graph, failed, pluginErrors);
    }
    return kExitUsage;
  }

  EvalOptions eval;
  if (!options.outDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.outDir, ec);
    if (ec) {
      printError(quotePath(options.outDir) + ": cannot create the output folder: " + ec.message());
      return kExitUsage;
    }
    eval.outputDir = options.outDir;
  }
  return evaluateAndReport(graph, registry, eval,
                           {options.graph, options.json, options.quiet, false, options.progress},
                           pluginErrors)
                 .ok
             ? kExitOk
             : kExitEvaluation;
}

EvalReport evaluateWithProgress(Evaluator& evaluator, const Graph& graph, EvalOptions eval,
                                const ReportOptions& options) {
  ProgressPrinter progress(progressMode(options));
  eval.progress = [&](const std::string& node, double fraction) {
    progress.update(node, fraction);
  };
  return evaluator.evaluate(graph, eval);
}

EvalReport evaluateAndReport(const Graph& graph, const NodeRegistry& registry, EvalOptions eval,
                             const ReportOptions& options,
                             const std::vector<std::string>& pluginErrors, Evaluator* evaluator) {
  Evaluator own(registry);
  Evaluator& used = evaluator ? *evaluator : own;
  const EvalReport report = evaluateWithProgress(used, graph, eval, options);
  std::map<std::string, double> metrics;
  if (report.ok) metrics = collectMetrics(graph, registry, used).values;

  if (!options.quiet && !options.json) {
    for (const auto& run : report.runs)
      for (const auto& warning : run.warnings)
        printWarning(escapeText(options.name.native(), 4096) + ": node " + quoteText(run.node) +
                     ": " + warning);
    for (const auto& file : report.filesWritten)
      std::fprintf(stderr, "wrote %s\n", messageLine(file.native()).c_str());
    for (const auto& [name, value] : options.printMetrics ? metrics : decltype(metrics){})
      std::fprintf(stderr, "%s = %s\n", messageLine(name).c_str(), formatParam(value).c_str());
  }
  if (!report.ok) printError(report.error);
  if (options.json) std::cout << runReportJson(options.name, report, pluginErrors, metrics);
  return report;
}

int validateGraph(const std::filesystem::path& path, bool quiet) {
  NodeRegistry registry;
  loadPlugins(registry, quiet);
  try {
    Graph graph = readGraphFile(path);
    prepareGraph(graph, registry);
    if (!quiet)
      std::printf("%s: ok (%zu nodes, %zu connections)\n", messageLine(path.native()).c_str(),
                  graph.nodes.size(), graph.connections.size());
    return kExitOk;
  } catch (const GraphError& e) {
    printError(e.what());
    return kExitUsage;
  }
}

int listNodes(bool json) {
  NodeRegistry registry;
  loadPlugins(registry, json);
  if (json) {
    std::cout << nodeTypesJson(registry);
    return kExitOk;
  }
  for (const NodeType* type : registry.types()) {
    std::printf("%s (v%d)  %s\n", type->id.c_str(), type->version, type->doc.c_str());
    for (const auto& port : type->inputs)
      std::printf("    in  %-14s %-20s %s%s\n", port.name.c_str(), port.typeId.c_str(),
                  port.doc.c_str(), port.optional ? " (optional)" : "");
    for (const auto& port : type->outputs)
      std::printf("    out %-14s %-20s %s\n", port.name.c_str(), port.typeId.c_str(),
                  port.doc.c_str());
    for (const auto& param : type->params)
      std::printf("    param %-12s %-12s = %-10s %s\n", param.name.c_str(),
                  std::string(toString(param.kind)).c_str(),
                  formatParam(param.defaultValue).c_str(), param.doc.c_str());
    std::printf("    from %s\n\n", type->library.c_str());
  }
  return kExitOk;
}

int renderFiles(const RenderCommandOptions& options) {
  // Distinct, colour-blind-safe hues for several meshes in one picture.
  static const Rgb kPalette[] = {{0.80f, 0.80f, 0.82f}, {0.90f, 0.60f, 0.00f},
                                 {0.34f, 0.71f, 0.91f}, {0.00f, 0.62f, 0.45f},
                                 {0.80f, 0.47f, 0.65f}, {0.94f, 0.89f, 0.26f}};
  std::vector<RenderItem> items;
  for (std::size_t i = 0; i < options.meshes.size(); ++i) {
    try {
      auto loaded = readMesh(options.meshes[i]);
      // The reader's warnings name the file already.
      for (const auto& warning : loaded.warnings)
        printWarning(warning);
      RenderItem item;
      item.mesh = loaded.mesh;
      item.color = kPalette[i % std::size(kPalette)];
      item.wireframe = options.wireframe;
      items.push_back(std::move(item));
    } catch (const std::exception& e) {
      printError(e.what());
      return kExitUsage;
    }
  }
  RenderResult result;
  try {
    result = renderMeshes(items, options.render);
  } catch (const std::exception& e) {
    printError(e.what());
    return kExitEvaluation;
  }
  try {
    // Its errors name the file (and refuse one that is not a regular file: a device, a FIFO).
    writePng(result.image, options.output);
  } catch (const std::exception& e) {
    printError(e.what());
    return kExitEvaluation;
  }
  std::fprintf(
      stderr, "%s\n",
      messageLine("wrote " + options.output.native() + " (" + std::to_string(result.image.width) +
                  "x" + std::to_string(result.image.height) + ", " + result.backend + ": " +
                  result.device + ")")
          .c_str());
  return kExitOk;
}

}  // namespace geobrush::cli
