// Every saved graph in graphs/ is evaluated headless and its outputs checked:
// written meshes are valid, written images show something, and a second run
// from scratch writes bit-identical files.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

std::vector<std::string> graphFiles() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourceDir() / "graphs"))
    if (entry.path().extension() == ".json") files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

EvalReport runGraph(const std::filesystem::path& file, const std::filesystem::path& outDir) {
  Graph graph = readGraphFile(file);
  prepareGraph(graph, test::registry());
  EvalOptions options;
  options.outputDir = outDir;
  Evaluator evaluator(test::registry());
  return evaluator.evaluate(graph, options);
}

void checkMeshFile(const std::filesystem::path& path) {
  auto loaded = readMesh(path);
  const MeshStats stats = meshStats(loaded.mesh->surface);
  EXPECT_GT(stats.faces, 0u) << path;
  EXPECT_EQ(stats.nonFiniteVertices, 0u) << path;
  EXPECT_EQ(stats.isolatedVertices, 0u) << path;
  EXPECT_TRUE(loaded.warnings.empty()) << path << ": " << loaded.warnings.front();
}

void checkImageFile(const std::filesystem::path& path) {
  const Image image = readPng(path);
  ASSERT_GT(image.width, 0);
  // Something other than the background: at least 5% of pixels differ from the corner.
  const std::uint8_t* corner = image.pixel(0, 0);
  std::size_t different = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      different += !std::equal(corner, corner + 3, image.pixel(x, y));
  EXPECT_GT(different, std::size_t(image.width) * image.height / 20) << path;
}

class SavedGraph : public testing::TestWithParam<std::string> {};

}  // namespace

TEST(SavedGraphs, ThereIsADefaultGraph) {
  const auto files = graphFiles();
  EXPECT_NE(std::find(files.begin(), files.end(), "default.json"), files.end());
}

TEST_P(SavedGraph, RunsAndWritesValidDeterministicOutputs) {
  const auto file = test::sourceDir() / "graphs" / GetParam();
  const auto first = test::tempDir("graph-a-" + GetParam());
  const auto second = test::tempDir("graph-b-" + GetParam());
  const EvalReport a = runGraph(file, first);
  ASSERT_TRUE(a.ok) << a.error;
  ASSERT_FALSE(a.filesWritten.empty()) << "a saved graph should write what it makes";
  for (const auto& path : a.filesWritten) {
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    const auto ext = path.extension().string();
    if (ext == ".png")
      checkImageFile(path);
    else
      checkMeshFile(path);
  }
  const EvalReport b = runGraph(file, second);
  ASSERT_TRUE(b.ok) << b.error;
  ASSERT_EQ(a.filesWritten.size(), b.filesWritten.size());
  for (std::size_t i = 0; i < a.filesWritten.size(); ++i) {
    EXPECT_EQ(a.filesWritten[i].filename(), b.filesWritten[i].filename());
    EXPECT_TRUE(bytes(a.filesWritten[i]) == bytes(b.filesWritten[i]))
        << a.filesWritten[i] << " differs between two runs";
  }
}

INSTANTIATE_TEST_SUITE_P(Graphs, SavedGraph, testing::ValuesIn(graphFiles()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(0, info.param.size() - 5);
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// The clone graphs paste onto closed targets: the result stays one closed manifold piece, and a
// pasted handle adds one to the genus (Euler characteristic 2 - 2 genus).
TEST(CloneGraphs, ResultsAreClosedManifoldsOfTheExpectedGenus) {
  struct Case {
    std::string graph, result;
    int eulerCharacteristic;
  };
  const std::vector<Case> cases = {
      {"clone_ear_cube_edge.json", "ear_on_cube_edge.obj", 2},
      {"clone_mountain_sphere.json", "mountain_on_sphere.obj", 2},
      {"clone_boot_loop_sphere.json", "boot_loop_on_sphere.obj", 0},
  };
  for (const Case& c : cases) {
    const auto dir = test::tempDir("clone-" + c.graph);
    const EvalReport report = runGraph(test::sourceDir() / "graphs" / c.graph, dir);
    ASSERT_TRUE(report.ok) << c.graph << ": " << report.error;
    const auto loaded = readMesh(dir / c.result);
    EXPECT_TRUE(loaded.warnings.empty()) << c.graph;
    const MeshStats stats = meshStats(loaded.mesh->surface);
    EXPECT_EQ(stats.boundaryLoops, 0u) << c.graph;
    EXPECT_EQ(stats.components, 1u) << c.graph;
    EXPECT_EQ(stats.eulerCharacteristic, c.eulerCharacteristic) << c.graph;
  }
}

// Painting the whole canvas, or solving on the smallest grid, still gives a closed manifold.
TEST(CloneGraphs, AWholeCanvasRegionAndACoarseGridStayValid) {
  for (const std::string assignment : {"strokes.dabs=0,0,5,1", "roi.resolution=16"}) {
    Graph graph = readGraphFile(test::sourceDir() / "graphs" / "clone_ear_cube_edge.json");
    setParamFromText(graph, test::registry(), assignment);
    prepareGraph(graph, test::registry());
    EvalOptions options;
    const auto dir = test::tempDir("clone-variant");
    options.outputDir = dir;
    Evaluator evaluator(test::registry());
    const EvalReport report = evaluator.evaluate(graph, options);
    ASSERT_TRUE(report.ok) << assignment << ": " << report.error;
    const MeshStats stats = meshStats(readMesh(dir / "ear_on_cube_edge.obj").mesh->surface);
    EXPECT_EQ(stats.boundaryLoops, 0u) << assignment;
    EXPECT_EQ(stats.components, 1u) << assignment;
    EXPECT_EQ(stats.eulerCharacteristic, 2) << assignment;
  }
}

// gc_warp connected to the region warps only the draft support; the pasted result is the same,
// bit for bit, as with the whole draft.
TEST(CloneGraphs, WarpingTheDraftSupportOnlyGivesTheSameResult) {
  for (const std::string name :
       {"clone_ear_cube_edge", "clone_mountain_sphere", "clone_boot_loop_sphere"}) {
    std::string results[2];
    for (int whole = 0; whole < 2; ++whole) {
      Graph graph = readGraphFile(test::sourceDir() / "graphs" / (name + ".json"));
      const Connection regionToWarp{{"roi", "region"}, {"warp", "region"}};
      const auto found =
          std::find(graph.connections.begin(), graph.connections.end(), regionToWarp);
      ASSERT_NE(found, graph.connections.end()) << name;
      if (whole) graph.connections.erase(found);
      prepareGraph(graph, test::registry());
      EvalOptions options;
      const auto dir = test::tempDir(name + (whole ? "-whole-draft" : "-support-draft"));
      options.outputDir = dir;
      Evaluator evaluator(test::registry());
      const EvalReport report = evaluator.evaluate(graph, options);
      ASSERT_TRUE(report.ok) << name << ": " << report.error;
      for (const auto& path : report.filesWritten)
        if (path.extension() == ".obj") results[whole] = bytes(path);
    }
    EXPECT_FALSE(results[0].empty()) << name;
    EXPECT_TRUE(results[0] == results[1]) << name;
  }
}
