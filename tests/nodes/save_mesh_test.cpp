#include "save_mesh.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <fstream>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;
using OpenMesh::Vec3d;

Mesh unitTetrahedron() {
  return test::tetrahedron({Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1)});
}

std::string planError(const Mesh& mesh, const fs::path& destination) {
  try {
    planMeshSave(mesh, {destination});
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

std::vector<fs::path> filesUnder(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    files.push_back(entry.path());
  return files;
}

TEST(SaveMesh, TakesTheFormatFromTheExtension) {
  const auto dir = test::tempDir("save-mesh-format");
  EXPECT_EQ(planMeshSave(unitTetrahedron(), {dir / "a.obj"}).format, MeshFormat::Obj);
  EXPECT_EQ(planMeshSave(unitTetrahedron(), {dir / "a.PLY"}).format, MeshFormat::Ply);
  EXPECT_EQ(planMeshSave(unitTetrahedron(), {dir / "a.off"}).format, MeshFormat::Off);
  EXPECT_EQ(planMeshSave(unitTetrahedron(), {dir / "a.Stl"}).format, MeshFormat::Stl);
  for (const char* name : {"a.obj", "a.ply", "a.off", "a.stl"})
    EXPECT_TRUE(planMeshSave(unitTetrahedron(), {dir / name}).warnings.empty()) << name;
}

TEST(SaveMesh, RefusesWhatCannotBeWrittenBeforeWritingAnything) {
  const auto dir = test::tempDir("save-mesh-refuse");
  const Mesh mesh = unitTetrahedron();
  EXPECT_EQ(planError(mesh, ""), "no file given");
  EXPECT_EQ(planError(mesh, dir / "a.xyz"),
            test::quoted(dir / "a.xyz") +
                ": unknown mesh format '.xyz' (supported: .obj, .ply, .off, "
                ".stl)");
  const auto intoMissing = dir / "missing" / "deeper" / "a.obj";
  EXPECT_EQ(planError(mesh, intoMissing), test::quoted(intoMissing) + ": the folder " +
                                              test::quoted(dir / "missing" / "deeper") +
                                              " does not exist");
  fs::create_directory(dir / "taken.obj");
  EXPECT_EQ(planError(mesh, dir / "taken.obj"), test::quoted(dir / "taken.obj") + ": is a folder");

  Mesh broken = mesh;
  broken.surface.set_point(TriMesh::VertexHandle(1), Vec3d(std::nan(""), 0, 0));
  EXPECT_TRUE(
      test::contains(planError(broken, dir / "a.obj"),
                     test::quoted(dir / "a.obj") + ": vertex 1 (0-based) has a non-finite"));
  const Mesh far =
      test::tetrahedron({Vec3d(0, 0, 0), Vec3d(1e39, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1)});
  EXPECT_TRUE(
      test::contains(planError(far, dir / "a.stl"), "beyond the 32-bit float range of STL"));
  EXPECT_EQ(planError(far, dir / "a.obj"), "");

  EXPECT_EQ(filesUnder(dir), std::vector<fs::path>{dir / "taken.obj"});
}

TEST(SaveMesh, WarnsAboutWhatTheFormatCannotHold) {
  const auto dir = test::tempDir("save-mesh-warn");
  const Mesh coloured(unitTetrahedron().surface, std::vector<Rgb>(4, Rgb{1, 0, 0}));
  const auto colours = planMeshSave(coloured, {dir / "a.obj"}).warnings;
  EXPECT_EQ(colours, std::vector<std::string>{test::quoted(dir / "a.obj") +
                                              ": vertex colours are not saved (only points and "
                                              "faces are)"});

  // 1/3 and 0.1 are no 32-bit floats; 0.5 and 1 are.
  const Mesh thirds =
      test::tetrahedron({Vec3d(1.0 / 3, 0, 0), Vec3d(1, 0.1, 0), Vec3d(0, 1, 0.5), Vec3d(0, 0, 1)});
  EXPECT_TRUE(planMeshSave(thirds, {dir / "a.obj"}).warnings.empty());
  const auto rounded = planMeshSave(thirds, {dir / "a.ply"}).warnings;
  ASSERT_EQ(rounded.size(), 1u);
  char largest[32];
  std::snprintf(largest, sizeof largest, "%.3g", std::abs(1.0 / 3 - double(float(1.0 / 3))));
  EXPECT_EQ(rounded[0], test::quoted(dir / "a.ply") +
                            ": PLY holds 32-bit floats: 2 coordinates rounded, by up to " +
                            largest + " (OBJ keeps them exact)");

  // STL keeps triangle corners only: an isolated vertex is lost, and copies at one position merge.
  TriMesh split = unitTetrahedron().surface;
  split.add_vertex(Vec3d(5, 5, 5));
  const auto a = split.add_vertex(Vec3d(0, 0, 0)), b = split.add_vertex(Vec3d(1, 0, 0)),
             c = split.add_vertex(Vec3d(0, -1, 0));
  split.add_face(a, b, c);
  const auto stl = planMeshSave(Mesh(split), {dir / "a.stl"}).warnings;
  EXPECT_EQ(stl, (std::vector<std::string>{
                     test::quoted(dir / "a.stl") +
                         ": STL holds triangles only: 1 vertex of no face is not saved",
                     test::quoted(dir / "a.stl") +
                         ": STL holds triangle corners only: 2 vertices share their position "
                         "with another and will be merged with it on reading"}));
  EXPECT_TRUE(planMeshSave(Mesh(split), {dir / "a.off"}).warnings.empty());
}

TEST(SaveMesh, ThePlannedFormatWinsOverATemporaryName) {
  const auto dir = test::tempDir("save-mesh-temporary");
  const Mesh mesh = unitTetrahedron();
  const SaveMeshPlan plan = planMeshSave(mesh, {dir / "result.stl"});
  writeMesh(mesh, dir / ".result.tmp-7-0", plan.format);
  fs::rename(dir / ".result.tmp-7-0", dir / "result.stl");
  EXPECT_EQ(fs::file_size(dir / "result.stl"), 84u + 4u * 50u);
  const auto back = readMesh(dir / "result.stl").mesh;
  EXPECT_EQ(back->surface.n_faces(), 4u);
  EXPECT_EQ(back->surface.n_vertices(), 4u);
}

// ------------------------------------------------------------------------------------------------
// The node, through the plugin and the evaluator.

TEST(SaveMeshNode, DeclaresItsPortsAndParams) {
  const NodeType* type = test::registry().find("geobrush.save_mesh");
  ASSERT_NE(type, nullptr);
  EXPECT_EQ(type->version, 1);
  ASSERT_EQ(type->inputs.size(), 1u);
  EXPECT_EQ(type->inputs[0].name, "mesh");
  EXPECT_EQ(type->inputs[0].typeId, Mesh::kTypeId);
  EXPECT_TRUE(type->outputs.empty());
  const ParamDecl* path = type->findParam("path");
  ASSERT_NE(path, nullptr);
  EXPECT_EQ(path->kind, ParamKind::OutputPath);
  EXPECT_EQ(std::get<std::string>(path->defaultValue), "result.obj");
  EXPECT_TRUE(type->writesFiles());
}

// source (load_mesh) -> one save_mesh node per entry of `saves` (node name -> path).
Graph saveGraph(const fs::path& file, const fs::path& input,
                const std::map<std::string, std::string>& saves) {
  Graph graph;
  graph.file = file;
  graph.nodes["source"] = GraphNode{"geobrush.load_mesh", 1, {{"path", input.string()}}};
  for (const auto& [name, path] : saves) {
    graph.nodes[name] = GraphNode{"geobrush.save_mesh", 1, {{"path", path}}};
    graph.connections.push_back({{"source", "mesh"}, {name, "mesh"}});
  }
  prepareGraph(graph, test::registry());
  return graph;
}

TEST(SaveMeshNode, WritesIntoTheOutputFolderExactly) {
  const auto dir = test::tempDir("save-mesh-node");
  const auto out = dir / "out";
  fs::create_directory(out);
  const auto input = test::meshPath("bunny_small.obj");
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.outputDir = out;
  const EvalReport report = evaluator.evaluate(
      saveGraph(dir / "graph.json", input, {{"obj", "bunny.obj"}, {"ply", "bunny.ply"}}), options);
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_EQ(report.filesWritten, (std::vector<fs::path>{out / "bunny.obj", out / "bunny.ply"}));
  EXPECT_EQ(filesUnder(out).size(), 2u);
  const auto source = std::dynamic_pointer_cast<const Mesh>(evaluator.output("source", "mesh"));
  ASSERT_TRUE(source);
  EXPECT_EQ(readMesh(out / "bunny.obj").mesh->contentHash(), source->contentHash());
  EXPECT_EQ(readMesh(out / "bunny.ply").mesh->surface.n_faces(), 3674u);
  // The shipped coordinates have more digits than a float: the PLY save says so.
  const auto ply = std::find_if(report.runs.begin(), report.runs.end(),
                                [](const NodeRun& run) { return run.node == "ply"; });
  ASSERT_NE(ply, report.runs.end());
  ASSERT_EQ(ply->warnings.size(), 1u);
  EXPECT_TRUE(test::contains(ply->warnings[0], "PLY holds 32-bit floats"));
}

TEST(SaveMeshNode, WritesNothingWhenAnySaveFails) {
  const auto dir = test::tempDir("save-mesh-node-fail");
  const auto input = test::meshPath("sphere.obj");
  Evaluator evaluator(test::registry());
  // "a" is written first, then "b" fails: neither file may appear.
  const EvalReport report = evaluator.evaluate(
      saveGraph(dir / "graph.json", input, {{"a", "a.obj"}, {"b", "missing/b.obj"}}));
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(test::contains(report.error, "param 'path'"));
  EXPECT_TRUE(test::contains(report.error, test::quoted(dir / "missing" / "b.obj") +
                                               ": the folder " + test::quoted(dir / "missing") +
                                               " does not exist"));
  EXPECT_TRUE(report.filesWritten.empty());
  EXPECT_EQ(filesUnder(dir), std::vector<fs::path>{});
}

TEST(SaveMeshNode, RefusesAnUnknownExtensionOnThePathParam) {
  const auto dir = test::tempDir("save-mesh-node-ext");
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(
      saveGraph(dir / "graph.json", test::meshPath("sphere.obj"), {{"sink", "sphere.glb"}}));
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(test::contains(report.error, "param 'path'"));
  EXPECT_TRUE(test::contains(report.error, "unknown mesh format '.glb'"));
  EXPECT_EQ(filesUnder(dir), std::vector<fs::path>{});
}

// An existing destination must be a regular file or a link to one: renaming the saved file over
// a FIFO (or a device, as /dev/full) would replace it.
TEST(SaveMeshNode, NeverReplacesAFifo) {
  const auto dir = test::tempDir("save-mesh-node-fifo");
  const auto fifo = dir / "mesh.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(
      saveGraph(dir / "graph.json", test::meshPath("sphere.obj"), {{"sink", "mesh.obj"}}));
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(test::contains(
      report.error, "graph.json: node 'sink' param 'path': " + test::quoted(fifo) + ": is a FIFO"));
  EXPECT_TRUE(report.filesWritten.empty());
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(filesUnder(dir), std::vector<fs::path>{fifo});
}

// Written through the link: the link stays, the file it names is replaced, and the temporary
// file is made beside that file (a rename is atomic only within one folder).
TEST(SaveMeshNode, WritesThroughASymlink) {
  const auto dir = test::tempDir("save-mesh-node-symlink");
  fs::create_directory(dir / "real");
  std::ofstream(dir / "real" / "sphere.obj") << "old";
  fs::create_symlink(fs::path("real") / "sphere.obj", dir / "link.obj");
  Evaluator evaluator(test::registry());
  const auto input = test::meshPath("sphere.obj");
  const EvalReport report =
      evaluator.evaluate(saveGraph(dir / "graph.json", input, {{"sink", "link.obj"}}));
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_EQ(report.filesWritten, std::vector<fs::path>{dir / "link.obj"});
  EXPECT_TRUE(fs::is_symlink(dir / "link.obj"));
  EXPECT_EQ(readMesh(dir / "real" / "sphere.obj").mesh->contentHash(),
            readMesh(input).mesh->contentHash());
  auto files = filesUnder(dir);
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files,
            (std::vector<fs::path>{dir / "link.obj", dir / "real", dir / "real" / "sphere.obj"}));
}

// Two saves of one file would both report writing it, and one mesh would be lost.
TEST(SaveMeshNode, TwoSavesOfOneFileAreRefusedBeforeAnythingRuns) {
  const auto dir = test::tempDir("save-mesh-node-twice");
  const auto input = test::meshPath("sphere.obj");
  try {
    saveGraph(dir / "graph.json", input, {{"a", "m.obj"}, {"b", "sub/../m.obj"}});
    ADD_FAILURE() << "two saves of m.obj";
  } catch (const GraphError& e) {
    EXPECT_TRUE(test::contains(e.what(),
                               "node 'b' param 'path': writes 'm.obj', as node 'a' param 'path'"));
  }
  // An absolute path and a relative one meet in the output folder, known when evaluating.
  const auto out = dir / "out";
  fs::create_directory(out);
  const Graph graph =
      saveGraph(dir / "graph.json", input, {{"a", (out / "m.obj").string()}, {"b", "m.obj"}});
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.outputDir = out;
  const EvalReport report = evaluator.evaluate(graph, options);
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(test::contains(report.error, "node 'b' param 'path': writes " +
                                               test::quoted(out / "m.obj") +
                                               ", as node 'a' param 'path' does"));
  EXPECT_TRUE(report.runs.empty()) << "refused before any node ran";
  EXPECT_TRUE(filesUnder(out).empty());
}

}  // namespace
}  // namespace geobrush
