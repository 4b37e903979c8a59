// The `geobrush` subcommands, independent of how the command line is parsed.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/clone.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/render.hpp"

namespace geobrush::cli {

// Exit statuses (DESIGN.md, "Command line").
inline constexpr int kExitOk = 0;
inline constexpr int kExitEvaluation = 1;
inline constexpr int kExitUsage = 2;

struct RunOptions {
  std::filesystem::path graph;
  std::vector<std::string> sets;  // NODE.PARAM=VALUE
  std::filesystem::path outDir;
  bool json = false;
  bool quiet = false;
  bool progress = false;  // progress as plain lines, even when stderr is no terminal
};

struct RenderCommandOptions {
  std::vector<std::filesystem::path> meshes;
  std::filesystem::path output;
  RenderOptions render;
  bool wireframe = false;
};

struct CompareOptions {
  std::filesystem::path graphA, graphB;
  std::vector<std::string> sets;  // NODE.PARAM=VALUE, applied to both graphs
  std::filesystem::path outDir = ".";
  std::filesystem::path image;  // empty: outDir / "compare.png"
  RenderOptions render;
  bool json = false;
  bool quiet = false;
  bool progress = false;
};

// One side of a comparison: its evaluation, every Metrics output flattened to "node.name", and
// the mesh its metrics node measured.
struct ComparedGraph {
  std::filesystem::path graph;
  EvalReport report;
  std::map<std::string, double> metrics;
  std::vector<std::string> notes;
  std::shared_ptr<const Mesh> mesh;
  std::shared_ptr<const PasteMap> map;  // what the metrics node was given, if anything
};

// How an evaluation is reported: `name` is the graph file (or what stands for it) in messages.
struct ReportOptions {
  std::filesystem::path name;
  bool json = false;
  bool quiet = false;
  bool printMetrics = false;  // each Metrics value as a line "node.name = value" on stderr
  // Progress as plain lines (for logs); otherwise a status line on a terminal, unless quiet.
  bool progressLines = false;
};

struct CloneOptions {
  CloneRequest request;  // an empty output mesh: SOURCE_on_TARGET.obj here
  std::filesystem::path saveGraph;
  bool json = false;
  bool quiet = false;
  bool progress = false;
};

struct FillOptions {
  std::filesystem::path mesh;
  std::filesystem::path output;
  std::filesystem::path image;  // empty: no picture
  std::string holes = "all";    // all, all-but-largest or loop ids like 0,2
  int maxBorder = 0;            // 0: no limit
  int continuity = 1;
  bool json = false;
  bool quiet = false;
  bool progress = false;
};

int runGraph(const RunOptions& options);
// Fills the chosen boundary loops of a mesh (the fill_holes node) and writes the result, and a
// picture when asked; per loop, what was added or why it stays open.
int fillHoles(const FillOptions& options);
// Whether --holes is all, all-but-largest or a comma-separated list of loop ids.
bool isHoleChoice(const std::string& holes);
// Fills a clone method with the spec (points snapped to their meshes), applies --set, evaluates
// it and writes the result mesh (and picture, and the filled graph when asked).
int cloneMeshes(const CloneOptions& options);
int listMethods();
// Evaluates both graphs (each writing its files under outDir/<graph name>), prints their metrics
// and node times side by side and writes both measured meshes into one PNG. Nothing is written
// but the graphs' own outputs when either fails.
int compareGraphs(const CompareOptions& options);
int validateGraph(const std::filesystem::path& graph, bool quiet);
int listNodes(bool json);
int renderFiles(const RenderCommandOptions& options);

// One line on stderr, "error: ..." or "warning: ...": escaped and bounded (text.hpp's
// messageLine), as messages quote names and texts from files and command lines.
void printError(const std::string& message);
void printWarning(const std::string& message);

// Loads the plugins of defaultPluginDirs(); returns the refusals, printed unless quiet.
std::vector<std::string> loadPlugins(NodeRegistry& registry, bool quiet);
// Evaluates with the progress `options` asks for on stderr (a status line on a terminal unless
// quiet, or plain lines), and prints nothing else.
EvalReport evaluateWithProgress(Evaluator& evaluator, const Graph& graph, EvalOptions eval,
                                const ReportOptions& options);
// For each metric with a known direction (and node times): "a" or "b" for the side whose value
// is better, "=" when both are equal; "" when either lacks it or its direction is unknown.
std::string betterSide(const std::string& key, const std::map<std::string, double>& a,
                       const std::map<std::string, double>& b);
// Evaluates with a progress line on a terminal, then prints warnings, the files written and the
// error (or the JSON report), as `geobrush run` does. Uses `evaluator` when given.
EvalReport evaluateAndReport(const Graph& graph, const NodeRegistry& registry, EvalOptions eval,
                             const ReportOptions& options,
                             const std::vector<std::string>& pluginErrors,
                             Evaluator* evaluator = nullptr);

// JSON texts (report_json.cpp keeps nlohmann_json in one file).
// With metrics, a "metrics" object of them.
std::string runReportJson(const std::filesystem::path& graph, const EvalReport& report,
                          const std::vector<std::string>& pluginErrors,
                          const std::map<std::string, double>& metrics = {});
// runReportJson's report of a fill, plus "holes": one object per boundary loop (loop,
// border_edges, filled, new_vertices, new_faces, time_ms, ...) and the fill's notes.
std::string fillReportJson(const std::filesystem::path& mesh, const EvalReport& report,
                           const std::vector<std::string>& pluginErrors,
                           const std::map<std::string, double>& metrics,
                           const std::vector<std::string>& notes);
std::string nodeTypesJson(const NodeRegistry& registry);
std::string compareReportJson(const ComparedGraph& a, const ComparedGraph& b,
                              const std::filesystem::path& image, const std::string& error);

}  // namespace geobrush::cli
