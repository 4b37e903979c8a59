#include "test_support.hpp"

#include <algorithm>
#include <fstream>

#include <gtest/gtest.h>

#include <unistd.h>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/values.hpp"

namespace geobrush::test {

std::filesystem::path meshDir() {
  return std::filesystem::weakly_canonical(GEOBRUSH_MESH_DIR);
}
std::filesystem::path meshPath(const std::string& name) {
  return meshDir() / name;
}
std::filesystem::path sourceDir() {
  return GEOBRUSH_SOURCE_DIR;
}
std::filesystem::path pluginDir() {
  return GEOBRUSH_PLUGIN_DIR;
}
std::filesystem::path testPluginDir() {
  return GEOBRUSH_TEST_PLUGIN_DIR;
}
std::filesystem::path cliPath() {
  return GEOBRUSH_CLI;
}

namespace {
struct LoadedRegistry {
  NodeRegistry registry;
  std::vector<std::string> errors;
};
LoadedRegistry& loaded() {
  // Never destroyed: plugin code must outlive every value it made.
  static LoadedRegistry* instance = [] {
    auto* r = new LoadedRegistry();
    r->errors = r->registry.loadPlugins({pluginDir()}).errors;
    return r;
  }();
  return *instance;
}
}  // namespace

const NodeRegistry& registry() {
  return loaded().registry;
}
const std::vector<std::string>& registryLoadErrors() {
  return loaded().errors;
}

std::vector<std::string> shippedGraphs() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(sourceDir() / "graphs"))
    if (entry.path().extension() == ".json") files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  return files;
}

EvalReport runGraphFile(const std::filesystem::path& file, const std::filesystem::path& outDir) {
  Graph graph = readGraphFile(file);
  prepareGraph(graph, registry());
  EvalOptions options;
  options.outputDir = outDir;
  Evaluator evaluator(registry());
  return evaluator.evaluate(graph, options);
}

const NodeRegistry& testNodeRegistry() {
  static NodeRegistry* instance = [] {
    auto* r = new NodeRegistry();
    r->loadPlugins({testPluginDir()});
    return r;
  }();
  return *instance;
}

std::string quoted(const std::filesystem::path& path) {
  // Appending, not operator+: GCC 12 warns falsely (-Wrestrict) on "'" + string.
  std::string text = "'";
  text += path.string();
  text += '\'';
  return text;
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' lacks '" << part << "'";
}

std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::filesystem::path tempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("geobrush-test-" + std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  struct Cleanup {
    std::filesystem::path root;
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(root, ec);
    }
  };
  static std::vector<std::unique_ptr<Cleanup>> cleanups;
  cleanups.push_back(std::make_unique<Cleanup>());
  cleanups.back()->root = dir;
  return dir;
}

std::map<std::string, double> graphMetrics(Graph graph) {
  prepareGraph(graph, registry());
  EvalOptions options;
  static int runs = 0;
  options.outputDir =
      tempDir("metrics-" + graph.file.stem().string() + "-" + std::to_string(runs++));
  options.targets = {"metrics"};
  Evaluator evaluator(registry());
  const EvalReport report = evaluator.evaluate(graph, options);
  EXPECT_TRUE(report.ok) << report.error;
  const auto metrics =
      std::dynamic_pointer_cast<const Metrics>(evaluator.output("metrics", "metrics"));
  return metrics ? metrics->values : std::map<std::string, double>{};
}

std::map<std::string, double> graphMetrics(const std::filesystem::path& file,
                                           const std::vector<std::string>& assignments) {
  Graph graph = readGraphFile(file);
  for (const auto& assignment : assignments)
    setParamFromText(graph, registry(), assignment);
  return graphMetrics(std::move(graph));
}

bool isBackground(const std::uint8_t* rgba) {
  return rgba[0] == 255 && rgba[1] == 255 && rgba[2] == 255;
}

double coverage(const Image& image) {
  std::size_t covered = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      covered += !isBackground(image.pixel(x, y));
  return double(covered) / (double(image.width) * image.height);
}

}  // namespace geobrush::test
