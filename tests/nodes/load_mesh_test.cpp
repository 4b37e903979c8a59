#include "load_mesh.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;

fs::path writeFile(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path;
}

std::string loadError(const fs::path& path, const LoadMeshOptions& options = {}) {
  try {
    loadMesh(path, options);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

// Three triangles around one edge: the third makes it non-manifold.
const std::string kFin =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";

TEST(LoadMesh, ReadsAShippedMesh) {
  const LoadMeshResult result = loadMesh(test::meshPath("bunny_small.obj"));
  ASSERT_TRUE(result.mesh);
  EXPECT_EQ(result.mesh->surface.n_vertices(), 1839u);
  EXPECT_EQ(result.mesh->surface.n_faces(), 3674u);
  EXPECT_TRUE(result.warnings.empty());
}

// Each stage of the reading reports its end, rising to 1; what the callback throws stops it.
TEST(LoadMesh, ReportsProgressPerStage) {
  LoadMeshOptions options;
  std::vector<double> reports;
  options.progress = [&](double fraction) { reports.push_back(fraction); };
  ASSERT_TRUE(loadMesh(test::meshPath("bunny_small.obj"), options).mesh);
  EXPECT_EQ(reports, (std::vector<double>{0.2, 0.7, 0.9, 1.0}));
  options.progress = [](double fraction) {
    if (fraction > 0.5) throw std::runtime_error("cancelled");
  };
  EXPECT_THROW(loadMesh(test::meshPath("bunny_small.obj"), options), std::runtime_error);
}

TEST(LoadMesh, NeedsAPath) {
  EXPECT_EQ(loadError(""), "no file given");
}

TEST(LoadMesh, RepairSplitsNonManifoldFacesInsteadOfFailing) {
  const auto path = writeFile(test::tempDir("load-mesh-repair") / "fin.obj", kFin);
  EXPECT_TRUE(test::contains(loadError(path), "set repair to split them off"));
  const LoadMeshResult repaired = loadMesh(path, {.repair = true, .progress = {}});
  EXPECT_EQ(repaired.mesh->surface.n_faces(), 3u);
  EXPECT_EQ(repaired.mesh->surface.n_vertices(), 8u);
  ASSERT_EQ(repaired.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(repaired.warnings[0], "repaired 1 face"));
}

TEST(LoadMesh, PassesFileErrorsOn) {
  const auto dir = test::tempDir("load-mesh-errors");
  EXPECT_EQ(loadError(dir / "missing.obj"), test::quoted(dir / "missing.obj") + ": no such file");
  const auto points = writeFile(dir / "points.off", "OFF\n1 0 0\n0 0 0\n");
  EXPECT_TRUE(test::contains(loadError(points), "has 1 vertex but no faces"));
}

// ------------------------------------------------------------------------------------------------
// The node, through the plugin and the evaluator.

TEST(LoadMeshNode, DeclaresItsPortsAndParams) {
  const NodeType* type = test::registry().find("geobrush.load_mesh");
  ASSERT_NE(type, nullptr);
  EXPECT_EQ(type->version, 1);
  EXPECT_TRUE(type->inputs.empty());
  ASSERT_EQ(type->outputs.size(), 1u);
  EXPECT_EQ(type->outputs[0].name, "mesh");
  EXPECT_EQ(type->outputs[0].typeId, Mesh::kTypeId);
  const ParamDecl* path = type->findParam("path");
  ASSERT_NE(path, nullptr);
  EXPECT_EQ(path->kind, ParamKind::InputPath);
  const ParamDecl* repair = type->findParam("repair");
  ASSERT_NE(repair, nullptr);
  EXPECT_EQ(repair->kind, ParamKind::Bool);
  EXPECT_EQ(std::get<bool>(repair->defaultValue), false);
  EXPECT_FALSE(type->writesFiles());
}

Graph loadGraph(const fs::path& file, ParamMap params) {
  Graph graph;
  graph.file = file;
  graph.nodes["source"] = GraphNode{"geobrush.load_mesh", 1, std::move(params)};
  prepareGraph(graph, test::registry());
  return graph;
}

TEST(LoadMeshNode, LoadsRelativeToTheGraphFileWithWarnings) {
  const auto dir = test::tempDir("load-mesh-node");
  writeFile(dir / "meshes" / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const Graph graph = loadGraph(dir / "graph.json", {{"path", std::string("meshes/quad.obj")}});
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  const auto mesh = std::dynamic_pointer_cast<const Mesh>(evaluator.output("source", "mesh"));
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->surface.n_vertices(), 4u);
  EXPECT_EQ(mesh->surface.n_faces(), 2u);
  ASSERT_EQ(report.runs.size(), 1u);
  ASSERT_EQ(report.runs[0].warnings.size(), 1u);
  EXPECT_TRUE(test::contains(report.runs[0].warnings[0], "triangulated 1 polygon"));
}

TEST(LoadMeshNode, ReportsProblemsOnThePathParam) {
  const auto dir = test::tempDir("load-mesh-node-errors");
  writeFile(dir / "fin.obj", kFin);
  Evaluator evaluator(test::registry());

  const EvalReport missing =
      evaluator.evaluate(loadGraph(dir / "graph.json", {{"path", std::string("none.obj")}}));
  EXPECT_FALSE(missing.ok);
  EXPECT_TRUE(test::contains(missing.error, "param 'path'"));
  EXPECT_TRUE(test::contains(missing.error, (dir / "none.obj").string() + "': no such file"));

  const EvalReport empty = evaluator.evaluate(loadGraph(dir / "graph.json", {}));
  EXPECT_FALSE(empty.ok);
  EXPECT_TRUE(test::contains(empty.error, "param 'path'"));
  EXPECT_TRUE(test::contains(empty.error, "no file given"));

  const EvalReport refused =
      evaluator.evaluate(loadGraph(dir / "graph.json", {{"path", std::string("fin.obj")}}));
  EXPECT_FALSE(refused.ok);
  EXPECT_TRUE(test::contains(refused.error, "set repair to split them off"));

  const EvalReport repaired = evaluator.evaluate(
      loadGraph(dir / "graph.json", {{"path", std::string("fin.obj")}, {"repair", true}}));
  ASSERT_TRUE(repaired.ok) << repaired.error;
  EXPECT_EQ(repaired.runs[0].warnings.size(), 1u);
}

}  // namespace
}  // namespace geobrush
