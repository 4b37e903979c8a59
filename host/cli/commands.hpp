// The `geobrush` subcommands, independent of how the command line is parsed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "geobrush/evaluator.hpp"
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
};

struct RenderCommandOptions {
  std::vector<std::filesystem::path> meshes;
  std::filesystem::path output;
  RenderOptions render;
  bool wireframe = false;
};

int runGraph(const RunOptions& options);
int validateGraph(const std::filesystem::path& graph, bool quiet);
int listNodes(bool json);
int renderFiles(const RenderCommandOptions& options);

// JSON texts (report_json.cpp keeps nlohmann_json in one file).
std::string runReportJson(const std::filesystem::path& graph, const EvalReport& report,
                          const std::vector<std::string>& pluginErrors);
std::string nodeTypesJson(const NodeRegistry& registry);

}  // namespace geobrush::cli
