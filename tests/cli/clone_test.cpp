// `geobrush clone`: a method template filled from plain arguments reproduces the shipped clone
// graphs, makes valid pastes with its own defaults, saves a graph that runs to the same mesh, and
// keeps the command line's contract on bad arguments.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "geobrush/image.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "process.hpp"
#include "test_support.hpp"

using namespace geobrush;
using test::runCli;

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// "name = value" lines that the command prints for each metric.
double metric(const std::string& err, const std::string& name) {
  const auto at = err.find("\n" + name + " = ");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no metric " << name << " in:\n" << err;
    return -1;
  }
  return std::stod(err.substr(at + name.size() + 4));
}

struct Clone {
  std::string source, sourcePoint, radius, target, targetPoint, scale;
};

std::vector<std::string> cloneArgs(const Clone& clone, const fs::path& output) {
  return {"clone",
          "--source",
          test::meshPath(clone.source).string(),
          "--source-point",
          clone.sourcePoint,
          "--radius",
          clone.radius,
          "--target",
          test::meshPath(clone.target).string(),
          "--target-point",
          clone.targetPoint,
          "--scale",
          clone.scale,
          "-o",
          output.string()};
}

const Clone kMountainOnSphere{
    "mountain.obj", "0.068548,19.73209,0.029055", "6", "sphere.obj", "0,0,1", "0.05"};
const Clone kEarOnCubeEdge{
    "armadillo.obj", "0.102853,0.375548,0.167421", "0.07", "cube.obj", "1,0.2,1", "6"};
const Clone kBootLacesOnSphere{"boot.obj", "0.01837,0.11851,0.00119", "0.03", "sphere.obj", "0,0,1",
                               "8"};
// The lower half of the lacing: five crossings and their eyelets, handles the region cuts.
const Clone kBootLaceOnSphere{"boot.obj", "0.025,0.095,0.005", "0.025", "sphere.obj", "0,0,1", "8"};
const Clone kNefertitiOnBunny{"nefertiti.obj",  "3.55,-8.28,181.24",     "20",
                              "bunny_scan.obj", "-0.0035,0.0761,0.0588", "0.001"};

// The shipped graph's result mesh, as `geobrush run` writes it.
std::string shippedResult(const std::string& graph, const std::string& mesh) {
  const auto out = test::tempDir("clone-shipped-" + graph);
  const auto run = runCli(
      {"run", (test::sourceDir() / "graphs" / graph).string(), "--out", out.string(), "--quiet"});
  EXPECT_EQ(run.status, 0) << run.err;
  return slurp(out / mesh);
}

TEST(Clone, ReproducesTheShippedCloneGraphsFromPlainArguments) {
  // The shipped graphs chose their canvases by hand; --set gives the same one.
  const auto out = test::tempDir("clone-reproduce");
  auto mountain = cloneArgs(kMountainOnSphere, out / "mountain.obj");
  mountain.insert(mountain.end(), {"--set", "source_canvas.dabs=0.068548,19.73209,0.029055,8"});
  const auto a = runCli(mountain);
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_EQ(slurp(out / "mountain.obj"),
            shippedResult("clone_mountain_sphere.json", "mountain_on_sphere.obj"));

  auto ear = cloneArgs(kEarOnCubeEdge, out / "ear.obj");
  ear.insert(ear.end(), {"--set", "source_canvas.dabs=0.102853,0.375548,0.167421,0.1"});
  const auto b = runCli(ear);
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(slurp(out / "ear.obj"),
            shippedResult("clone_ear_cube_edge.json", "ear_on_cube_edge.obj"));
}

TEST(Clone, ItsOwnCanvasGivesAManifoldPasteWithoutNewSelfIntersections) {
  const auto out = test::tempDir("clone-defaults");
  for (const Clone& clone : {kMountainOnSphere, kEarOnCubeEdge, kNefertitiOnBunny}) {
    const auto result = runCli(cloneArgs(clone, out / (clone.source + ".obj")));
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_EQ(metric(result.err, "metrics.manifold"), 1) << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.components"), 1) << clone.source;
    // The scanned bunny's holes stay; the paste opens none.
    EXPECT_EQ(metric(result.err, "metrics.boundary_loops"),
              metric(result.err, "metrics.target_boundary_loops"))
        << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.new_self_intersections"), 0) << clone.source;
  }
}

TEST(Clone, SavesAGraphThatRunsToTheSameMeshAndSnapsItsPoints) {
  const auto out = test::tempDir("clone-save");
  Clone offSurface = kMountainOnSphere;
  offSurface.targetPoint = "0,0,1.5";  // half a radius above the sphere
  auto args = cloneArgs(offSurface, out / "clone.obj");
  args.insert(args.end(), {"--save-graph", (out / "clone.json").string(), "--image",
                           (out / "clone.png").string()});
  const auto clone = runCli(args);
  ASSERT_EQ(clone.status, 0) << clone.err;
  EXPECT_TRUE(test::contains(clone.err, "note: the target point moved 0.5"));
  // The picture frames the paste: the target's surface around it fills much more of the picture
  // than the whole target does.
  auto whole = cloneArgs(offSurface, out / "whole.obj");
  whole.insert(whole.end(),
               {"--set", "render_result.focus_radius=0", "--image", (out / "whole.png").string()});
  ASSERT_EQ(runCli(whole).status, 0);
  EXPECT_GT(test::coverage(readPng(out / "clone.png")),
            1.5 * test::coverage(readPng(out / "whole.png")));

  fs::create_directory(out / "again");
  const auto run = runCli({"run", (out / "clone.json").string(), "--quiet", "--set",
                           "save_result.path=" + (out / "again" / "clone.obj").string(), "--set",
                           "render_result.path=" + (out / "again" / "clone.png").string()});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(slurp(out / "again" / "clone.obj"), slurp(out / "clone.obj"));
}

TEST(Clone, ListsItsMethodsAndRunsTheVariationalPaste) {
  const auto list = runCli({"clone", "--list-methods"});
  EXPECT_EQ(list.status, 0);
  EXPECT_TRUE(test::contains(list.out, "geobrush "));
  EXPECT_TRUE(test::contains(list.out, "variational "));

  const auto out = test::tempDir("clone-variational");
  auto args = cloneArgs(kEarOnCubeEdge, out / "variational.obj");
  args.insert(args.end(), {"--method", "variational"});
  const auto result = runCli(args);
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_EQ(metric(result.err, "metrics.manifold"), 1);
  EXPECT_EQ(metric(result.err, "metrics.new_self_intersections"), 0);
}

TEST(Clone, BadArgumentsAreOneErrorLineAndWriteNothing) {
  const auto out = test::tempDir("clone-bad");
  const auto with = [&](std::vector<std::string> args, const std::string& option,
                        const std::string& value) {
    const auto at = std::find(args.begin(), args.end(), option);
    if (value.empty())
      args.erase(at, at + 2);
    else
      *(at + 1) = value;
    return args;
  };
  const auto base = cloneArgs(kMountainOnSphere, out / "never.obj");
  struct Case {
    std::vector<std::string> args;
    int status;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {with(base, "--source", ""), 2, "clone: --source is required"},
      {with(base, "--source", (out / "missing.obj").string()), 2, "error: source: '"},
      {with(base, "--radius", "-1"), 2, "--radius"},
      {with(base, "--source-point", "1,2"), 2, "--source-point: expected x,y,z, got '1,2'"},
      {with(base, "--scale", "1e-9"), 2, "node 'target_map' param 'scale': 1e-09 is outside"},
      {[&] {
         auto args = base;
         args.insert(args.end(), {"--method", "nothing"});
         return args;
       }(),
       2,
       "no clone method 'nothing' (methods: additive, cutpaste, dpm, emd, geobrush, variational"},
      // A target point far off: the region covers none of the target canvas; a node fails.
      {with(base, "--radius", "1000"), 1, "node '"},
  };
  for (const Case& c : cases) {
    const auto result = runCli(c.args);
    EXPECT_EQ(result.status, c.status) << result.err;
    EXPECT_EQ(result.errorLines(), 1) << result.err;
    EXPECT_TRUE(test::contains(result.err, c.expected));
    EXPECT_FALSE(fs::exists(out / "never.obj"));
  }
}

}  // namespace

// A paste wider than the feature under it (an ear tip of the bunny) folds over itself: the clone
// fails naming the metrics node and what is wrong, and writes nothing, unless asked to write it.
// The boot's lacing with the canvas the old shipped graph chose by hand: the region correction
// takes in the whole lacing up to the canvas' outline at the collar, where the seam cuts a lace
// and folds (13 face pairs, as CGAL's exact test counts them). The region correction warns
// where, and the clone refuses the paste and writes nothing.
TEST(Clone, TheBootLacingIsRefusedRatherThanWrittenFolded) {
  const auto out = test::tempDir("clone-boot");
  auto boot = cloneArgs(kBootLacesOnSphere, out / "boot.obj");
  boot.insert(boot.end(), {"--set", "source_canvas.dabs=0.01837,0.11851,0.00119,0.08", "--set",
                           "source_map.reversed_ring=1", "--set", "target_map.margin=0.5"});
  const auto refused = runCli(boot);
  EXPECT_EQ(refused.status, 1) << refused.err;
  EXPECT_TRUE(test::contains(refused.err, "the paste has 13 new self-intersections"))
      << refused.err;
  EXPECT_TRUE(test::contains(refused.err, "folded faces up to the source canvas' outline"))
      << refused.err;
  EXPECT_TRUE(fs::is_empty(out));
}

// Topology-free cut and paste on the same clones: a valid closed paste of the mountain, the ear,
// the relief and a lace of the boot (the source's detail over a minimal-area base, walked onto the
// target; handles need no cage).
TEST(Clone, TheCutPasteMethodGivesAManifoldPasteWithoutNewSelfIntersections) {
  EXPECT_TRUE(test::contains(runCli({"clone", "--list-methods"}).out, "cutpaste "));
  const auto out = test::tempDir("clone-cutpaste");
  for (const Clone& clone :
       {kMountainOnSphere, kEarOnCubeEdge, kNefertitiOnBunny, kBootLaceOnSphere}) {
    auto args = cloneArgs(clone, out / (clone.source + ".obj"));
    args.insert(args.end(), {"--method", "cutpaste"});
    const auto result = runCli(args);
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_EQ(metric(result.err, "metrics.manifold"), 1) << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.components"), 1) << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.boundary_loops"),
              metric(result.err, "metrics.target_boundary_loops"))
        << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.new_self_intersections"), 0) << clone.source;
  }
}

// The whole lacing's handles survive cut and paste too, but its seam folds where the region cuts
// the laces at the collar, as GeoBrush's does: the paste is refused, not written folded.
TEST(Clone, TheCutPasteMethodRefusesTheFoldedBootLacingToo) {
  const auto out = test::tempDir("clone-cutpaste-boot");
  auto args = cloneArgs(kBootLacesOnSphere, out / "boot.obj");
  args.insert(args.end(), {"--method", "cutpaste"});
  const auto refused = runCli(args);
  EXPECT_EQ(refused.status, 1) << refused.err;
  EXPECT_TRUE(test::contains(refused.err, "new self-intersections")) << refused.err;
  EXPECT_TRUE(fs::is_empty(out));
}

// EMD detail transfer on the same clones moves the target's own vertices: the result keeps the
// target's connectivity, valid and closed, whatever the detail the target's density can carry.
TEST(Clone, TheEmdMethodMovesTheTargetsOwnVerticesIntoAValidPaste) {
  EXPECT_TRUE(test::contains(runCli({"clone", "--list-methods"}).out, "emd "));
  const auto out = test::tempDir("clone-emd");
  for (const Clone& clone : {kMountainOnSphere, kEarOnCubeEdge, kNefertitiOnBunny}) {
    auto args = cloneArgs(clone, out / (clone.source + ".obj"));
    args.insert(args.end(), {"--method", "emd"});
    const auto result = runCli(args);
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_EQ(metric(result.err, "metrics.manifold"), 1) << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.new_self_intersections"), 0) << clone.source;
    EXPECT_GT(metric(result.err, "rebuild.unknowns"), 0) << clone.source;
    const MeshPtr target = readMesh(test::meshPath(clone.target)).mesh;
    const MeshPtr pasted = readMesh(out / (clone.source + ".obj")).mesh;
    EXPECT_EQ(test::faceIndices(pasted->surface), test::faceIndices(target->surface))
        << clone.source;
  }
}

// Projective cloning (GPU texture cloning paper): a valid paste where the source's view sees the
// region (the mountain; the ear, whose overhang the projection folds and the run reports), and a
// clear refusal, nothing written, where the target's stamp folds under its view (Nefertiti onto
// the scan's rough flank), which GeoBrush's exponential maps paste.
TEST(Clone, TheDpmMethodPastesWhereTheViewSeesTheRegionAndRefusesWhereItFolds) {
  EXPECT_TRUE(test::contains(runCli({"clone", "--list-methods"}).out, "dpm "));
  const auto out = test::tempDir("clone-dpm");
  for (const Clone& clone : {kMountainOnSphere, kEarOnCubeEdge}) {
    auto args = cloneArgs(clone, out / (clone.source + ".obj"));
    args.insert(args.end(), {"--method", "dpm"});
    const auto result = runCli(args);
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_EQ(metric(result.err, "metrics.manifold"), 1) << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.new_self_intersections"), 0) << clone.source;
    EXPECT_EQ(metric(result.err, "metrics.seam_unshared_vertices"), 0) << clone.source;
    const bool warnsOfFolds = result.err.find("canvas faces are folded") != std::string::npos;
    EXPECT_EQ(warnsOfFolds, clone.source == kEarOnCubeEdge.source) << result.err;
  }
  auto args = cloneArgs(kNefertitiOnBunny, out / "refused.obj");
  args.insert(args.end(), {"--method", "dpm"});
  const auto refused = runCli(args);
  EXPECT_EQ(refused.status, 1);
  EXPECT_TRUE(test::contains(refused.err, "node 'target_map' input 'mesh'"));
  EXPECT_TRUE(test::contains(refused.err, "fold under the view"));
  EXPECT_FALSE(std::filesystem::exists(out / "refused.obj"));
}

// A region about as small as the target's triangles (a relief plane onto a 642-vertex sphere)
// covers one target vertex or none: the target faces under R_in's outline are replaced all the
// same, and the paste is valid at every radius.
TEST(Clone, ASmallRegionOnACoarseSphereIsAValidPaste) {
  const auto out = test::tempDir("clone-coarse-sphere");
  {
    std::ofstream graph(out / "meshes.json");
    graph << R"({"format": "geobrush-graph", "formatVersion": 1,
      "nodes": {
        "sphere": {"type": "geobrush.primitive", "typeVersion": 1,
                   "params": {"shape": "sphere", "resolution": 8}},
        "plane": {"type": "geobrush.primitive", "typeVersion": 1,
                  "params": {"shape": "plane", "resolution": 32, "size": 2.0, "relief": 0.05}},
        "save_sphere": {"type": "geobrush.save_mesh", "typeVersion": 1,
                        "params": {"path": "sphere.obj"}},
        "save_plane": {"type": "geobrush.save_mesh", "typeVersion": 1,
                       "params": {"path": "plane.obj"}}},
      "connections": [{"from": "sphere.mesh", "to": "save_sphere.mesh"},
                      {"from": "plane.mesh", "to": "save_plane.mesh"}]})";
  }
  const auto meshes = runCli({"run", (out / "meshes.json").string(), "--quiet"});
  ASSERT_EQ(meshes.status, 0) << meshes.err;
  for (const char* radius : {"0.1", "0.15", "0.2"}) {
    SCOPED_TRACE(radius);
    const auto result =
        runCli({"clone", "--source", (out / "plane.obj").string(), "--source-point", "0,0,0",
                "--radius", radius, "--target", (out / "sphere.obj").string(), "--target-point",
                "0,0,1", "-o", (out / "paste.obj").string()});
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_EQ(metric(result.err, "metrics.manifold"), 1);
    EXPECT_EQ(metric(result.err, "metrics.new_self_intersections"), 0);
  }
}

TEST(Clone, AnInvalidPasteFailsAndWritesNothingUnlessAskedTo) {
  const auto out = test::tempDir("clone-invalid");
  const Clone onEarTip{"mountain.obj",    "0.068548,19.73209,0.029055",  "6",
                       "bunny_small.obj", "-0.479417,9.43959,-0.676324", "0.1313"};
  auto args = cloneArgs(onEarTip, out / "clone.obj");
  args.insert(args.end(), {"--image", (out / "clone.png").string()});
  const auto refused = runCli(args);
  EXPECT_EQ(refused.status, 1) << refused.err;
  EXPECT_TRUE(test::contains(refused.err, "node 'metrics' input 'mesh': the paste has "))
      << refused.err;
  EXPECT_TRUE(test::contains(refused.err, "new self-intersections")) << refused.err;
  EXPECT_TRUE(fs::is_empty(out));

  args.insert(args.end(), {"--set", "metrics.require_valid=false"});
  const auto written = runCli(args);
  ASSERT_EQ(written.status, 0) << written.err;
  EXPECT_GT(metric(written.err, "metrics.new_self_intersections"), 0);
  EXPECT_TRUE(fs::exists(out / "clone.obj"));
}
