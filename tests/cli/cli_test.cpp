// The geobrush program: commands, exit statuses, reports, and one clear
// error line with no output written for each kind of bad input.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "geobrush/image.hpp"
#include "geobrush/render.hpp"
#include "process.hpp"
#include "test_support.hpp"

using namespace geobrush;
using test::runCli;

namespace {

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A graph: load MESH -> save result.obj, in `dir`.
std::string loadSaveGraph(const std::string& meshPath) {
  return R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"load": {"type": "geobrush.load_mesh", "typeVersion": 1, "params": {"path": ")" +
         meshPath + R"("}},
              "save": {"type": "geobrush.save_mesh", "typeVersion": 1}},
    "connections": [{"from": "load.mesh", "to": "save.mesh"}]})";
}

bool isEmptyDir(const std::filesystem::path& dir) {
  return !std::filesystem::exists(dir) || std::filesystem::is_empty(dir);
}

// Every line of stderr is text a terminal shows as it is (no control characters: they are
// escaped) and bounded, whatever the files and arguments held.
::testing::AssertionResult printableBoundedLines(const std::string& err) {
  std::istringstream lines(err);
  for (std::string line; std::getline(lines, line);) {
    if (line.size() > 4096)
      return ::testing::AssertionFailure() << "a line of " << line.size() << " bytes";
    for (char c : line)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        return ::testing::AssertionFailure() << "a control character in: " << line;
  }
  return ::testing::AssertionSuccess();
}

std::vector<std::string> namesIn(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

struct BadCase {
  std::string name;
  std::string graph;                         // graph file text
  std::map<std::string, std::string> files;  // extra files beside it
  int status;
  std::string expected;  // part of the error line
  std::map<std::string, std::string> env = {};
};

// Keeps test names and failure messages readable.
void PrintTo(const BadCase& c, std::ostream* os) {
  *os << c.name;
}

class BadInput : public testing::TestWithParam<BadCase> {};

const char* kPrimitiveSave = R"({"format": "geobrush-graph", "formatVersion": 1,
  "nodes": {"shape": {"type": "geobrush.primitive", "typeVersion": 1},
            "save": {"type": "geobrush.save_mesh", "typeVersion": 1}},
  "connections": [{"from": "shape.mesh", "to": "save.mesh"}]})";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  return text.replace(text.find(from), from.size(), to);
}

std::vector<BadCase> badCases() {
  const std::string tetra =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  return {
      {"malformed_json",
       R"({"format": "geobrush-graph", "formatVersion": 1, "nodes": {)",
       {},
       2,
       "graph.json: malformed JSON"},
      {"wrong_format",
       replaced(kPrimitiveSave, "geobrush-graph", "blender"),
       {},
       2,
       "graph.json: not a GeoBrush graph"},
      {"newer_format",
       replaced(kPrimitiveSave, R"("formatVersion": 1)", R"("formatVersion": 7)"),
       {},
       2,
       "graph.json: formatVersion 7 was written by a newer GeoBrush"},
      {"unknown_type",
       replaced(kPrimitiveSave, "geobrush.primitive", "geobrush.teapot"),
       {},
       2,
       "graph.json: node 'shape': unknown node type 'geobrush.teapot': no loaded plugin provides "
       "it "
       "(expected plugin geobrush_teapot.so"},
      {"missing_node",
       replaced(kPrimitiveSave, "shape.mesh", "shap.mesh"),
       {},
       2,
       "graph.json: node 'shap' connection 'shap.mesh -> save.mesh': no node named 'shap'"},
      {"missing_port",
       replaced(kPrimitiveSave, "shape.mesh", "shape.image"),
       {},
       2,
       "graph.json: node 'shape' output 'image': 'geobrush.primitive' has no such output"},
      {"type_mismatch",
       R"({"format": "geobrush-graph", "formatVersion": 1,
          "nodes": {"n": {"type": "test.number", "typeVersion": 1},
                    "save": {"type": "geobrush.save_mesh", "typeVersion": 1}},
          "connections": [{"from": "n.value", "to": "save.mesh"}]})",
       {},
       2,
       "graph.json: node 'save' input 'mesh': type mismatch: it takes geobrush.Mesh but 'n.value' "
       "gives geobrush.Scalar",
       {{"GEOBRUSH_PLUGIN_PATH", test::testPluginDir().string()}}},
      {"cycle",
       R"({"format": "geobrush-graph", "formatVersion": 1,
          "nodes": {"a": {"type": "geobrush.transform", "typeVersion": 1},
                    "b": {"type": "geobrush.transform", "typeVersion": 1}},
          "connections": [{"from": "a.mesh", "to": "b.mesh"}, {"from": "b.mesh", "to": "a.mesh"}]})",
       {},
       2,
       "graph.json: node 'b': the graph has a cycle: 'b' -> 'a' -> 'b'"},
      {"bad_param",
       replaced(kPrimitiveSave, R"("typeVersion": 1},)",
                R"("typeVersion": 1, "params": {"resolution": "many"}},)"),
       {},
       2,
       "graph.json: node 'shape' param 'resolution': expected an integer"},
      {"missing_mesh",
       loadSaveGraph("nothing_here.obj"),
       {},
       1,
       "graph.json: node 'load' param 'path':"},
      {"nan_mesh",
       loadSaveGraph("nan.obj"),
       {{"nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"}},
       1,
       "graph.json: node 'load' param 'path':"},
      {"no_faces",
       loadSaveGraph("points.obj"),
       {{"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"}},
       1,
       "graph.json: node 'load' param 'path':"},
      {"non_manifold",
       loadSaveGraph("fan.obj"),
       {{"fan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"}},
       1,
       "graph.json: node 'load' param 'path':"},
      {"other_abi_plugin",
       R"({"format": "geobrush-graph", "formatVersion": 1,
          "nodes": {"x": {"type": "test.other_abi", "typeVersion": 1}}})",
       {},
       2,
       "graph.json: node 'x': node type 'test.other_abi' is unavailable: ",
       {{"GEOBRUSH_PLUGIN_PATH", test::testPluginDir().string()}}},
      {"node_throws",
       R"({"format": "geobrush-graph", "formatVersion": 1,
          "nodes": {"n": {"type": "test.number", "typeVersion": 1},
                    "f": {"type": "test.fail", "typeVersion": 1, "params": {"how": "std_exception"}},
                    "w": {"type": "test.write_text", "typeVersion": 1}},
          "connections": [{"from": "n.value", "to": "f.in"}, {"from": "f.value", "to": "w.value"}]})",
       {},
       1,
       "graph.json: node 'f': failed: a std::exception from the node",
       {{"GEOBRUSH_PLUGIN_PATH", test::testPluginDir().string()}}},
      {"number_out_of_range",
       replaced(kPrimitiveSave, R"("typeVersion": 1},)",
                R"("typeVersion": 1, "params": {"size": 1e309}},)"),
       {},
       2,
       "graph.json: node 'shape' param 'size': number out of range: 1e309"},
      {"ui_wrong_type",
       replaced(kPrimitiveSave, R"("connections")",
                R"("ui": {"shape": {"x": "left"}}, "connections")"),
       {},
       2,
       "graph.json: node 'shape' ui \"x\": must be a number"},
      {"duplicate_node",
       replaced(kPrimitiveSave, R"("save": {)",
                R"("shape": {"type": "geobrush.primitive", "typeVersion": 1}, "save": {)"),
       {},
       2,
       "graph.json: node 'shape': duplicate key \"shape\""},
      {"nul_in_save_path",
       replaced(kPrimitiveSave, R"("typeVersion": 1}},)",
                R"("typeVersion": 1, "params": {"path": "r.obj\u0000.obj"}}},)"),
       {},
       2,
       "graph.json: node 'save' param 'path': 'r.obj\\x00.obj': a path may not contain a NUL "
       "character"},
      {"control_characters_and_a_huge_text",
       replaced(kPrimitiveSave, R"("typeVersion": 1},)",
                R"("typeVersion": 1, "params": {"shape": "\u001b[2J\r\n)" +
                    std::string(100000, 'x') + R"("}},)"),
       {},
       2,
       "graph.json: node 'shape' param 'shape': '\\x1b[2J\\r\\nxxx"},
      {"good_tetra_bad_save_folder",
       replaced(loadSaveGraph("tetra.obj"), R"("typeVersion": 1}},)",
                R"("typeVersion": 1, "params": {"path": "no/such/folder/r.obj"}}},)"),
       {{"tetra.obj", tetra}},
       1,
       "graph.json: node 'save' param 'path': "},
  };
}

}  // namespace

TEST_P(BadInput, OneErrorLineNonZeroExitNoOutput) {
  const BadCase& c = GetParam();
  const auto dir = test::tempDir("cli-bad-" + c.name);
  writeText(dir / "graph.json", c.graph);
  for (const auto& [name, text] : c.files)
    writeText(dir / name, text);
  const auto out = dir / "out";
  auto result = runCli({"run", (dir / "graph.json").string(), "--out", out.string()}, c.env);
  EXPECT_EQ(result.status, c.status) << result.err;
  EXPECT_EQ(result.errorLines(), 1) << result.err;
  EXPECT_NE(result.err.find(c.expected), std::string::npos) << result.err;
  EXPECT_TRUE(printableBoundedLines(result.err));
  EXPECT_TRUE(isEmptyDir(out)) << "a failed run must write nothing";
}

INSTANTIATE_TEST_SUITE_P(Cli, BadInput, testing::ValuesIn(badCases()),
                         [](const testing::TestParamInfo<BadCase>& info) {
                           return info.param.name;
                         });

TEST(Cli, NodesJsonListsEachTypeFromItsOwnLibrary) {
  auto result = runCli({"nodes", "--json"});
  ASSERT_EQ(result.status, 0) << result.err;
  for (const char* name : {"load_mesh", "save_mesh", "primitive", "transform", "render"}) {
    EXPECT_NE(result.out.find(std::string("\"id\": \"geobrush.") + name + "\""), std::string::npos)
        << name;
    EXPECT_NE(result.out.find(std::string("/geobrush_") + name + ".so\""), std::string::npos)
        << name;
  }
  EXPECT_EQ(runCli({"nodes"}).status, 0);
}

TEST(Cli, RunsTheDefaultGraphAndReportsJson) {
  const auto out = test::tempDir("cli-default");
  auto result = runCli({"run", (test::sourceDir() / "graphs" / "default.json").string(), "--out",
                        out.string(), "--json"});
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_NE(result.out.find("\"ok\": true"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("\"cacheHits\": 0"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("\"seconds\":"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out / "default.obj"));
  EXPECT_TRUE(std::filesystem::exists(out / "default.png"));
  EXPECT_NE(result.out.find((out / "default.png").string()), std::string::npos);
}

// --progress: plain lines for logs, from each computed node's start to its end, with its time.
TEST(Cli, ProgressPrintsPlainLinesPerNode) {
  const auto out = test::tempDir("cli-progress");
  auto result = runCli({"run", (test::sourceDir() / "graphs" / "default.json").string(), "--out",
                        out.string(), "--progress"});
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_TRUE(printableBoundedLines(result.err));
  std::istringstream lines(result.err);
  int started = 0, ended = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("progress: [", 0) != 0) continue;
    started += line.find(" 0% ") != std::string::npos;
    ended += line.find(" 100% ") != std::string::npos;
    EXPECT_NE(line.find(" s"), std::string::npos) << line;
  }
  EXPECT_GE(started, 3) << result.err;
  EXPECT_EQ(started, ended) << result.err;
  // Without it, and with stderr no terminal, there is none.
  auto plain = runCli(
      {"run", (test::sourceDir() / "graphs" / "default.json").string(), "--out", out.string()});
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_EQ(plain.err.find("progress:"), std::string::npos) << plain.err;
}

// Drawing a field's legend needs a Qt platform plugin; where Qt has none for the platform asked
// for, the picture comes without its legend rather than Qt aborting the process.
TEST(Cli, AFieldRenderWithoutAQtPlatformPluginStillWritesItsPicture) {
  const auto out = test::tempDir("cli-no-qt-platform");
  writeText(out / "fields.json", R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"load": {"type": "geobrush.load_mesh", "typeVersion": 1, "params": {"path": ")" +
                                     test::meshPath("bunny_small.obj").string() + R"("}},
              "signal": {"type": "geobrush.emd_signal", "typeVersion": 1},
              "render": {"type": "geobrush.render", "typeVersion": 1,
                         "params": {"width": 160, "height": 120}}},
    "connections": [{"from": "load.mesh", "to": "signal.mesh"},
                    {"from": "load.mesh", "to": "render.mesh"},
                    {"from": "signal.signal", "to": "render.fields"}]})");
  const auto result = runCli({"run", (out / "fields.json").string(), "--out", out.string()},
                             {{"QT_QPA_PLATFORM", "no-such-platform"}});
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_TRUE(std::filesystem::exists(out / "render.png"));
}

// The table's row for a key, or "".
std::string rowOf(const std::string& table, const std::string& key) {
  std::istringstream lines(table);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(key + " ", 0) == 0) return line;
  return "";
}

// Two graphs side by side: their metrics and node times in one table that says which side is
// better in each measure with a direction, one picture of both, each framed on its paste and
// labelled with its graph's name.
TEST(Cli, CompareSetsTwoGraphsSideBySide) {
  const auto out = test::tempDir("cli-compare");
  const auto c1 = (test::sourceDir() / "graphs" / "compare_mountain_sphere_membrane.json");
  const auto c0 = (test::sourceDir() / "graphs" / "compare_mountain_sphere_membrane_c0.json");
  auto table = runCli({"compare", c1.string(), c0.string(), "--out", out.string()});
  ASSERT_EQ(table.status, 0) << table.err;
  EXPECT_NE(table.out.find("time_ms.membrane"), std::string::npos) << table.out;
  // The C1 membrane's seam is smoother than the C0 one's; both are manifold; an edge count has
  // no better side.
  EXPECT_TRUE(rowOf(table.out, "metrics.seam_normal_jump_p95_deg").ends_with(" a")) << table.out;
  EXPECT_TRUE(rowOf(table.out, "metrics.manifold").ends_with(" =")) << table.out;
  const std::string edges = rowOf(table.out, "metrics.seam_edges");
  ASSERT_FALSE(edges.empty());
  EXPECT_FALSE(edges.ends_with(" a") || edges.ends_with(" b") || edges.ends_with(" =")) << edges;

  const Image picture = readPng(out / "compare.png");
  const int half = RenderOptions().width;
  ASSERT_EQ(picture.width, 2 * half);
  for (int side = 0; side < 2; ++side) {
    // Framed on the paste: it lies at the centre of each half.
    EXPECT_FALSE(test::isBackground(picture.pixel(side * half + half / 2, picture.height / 2)));
    // A label of dark text in the top left corner, on the background there.
    int dark = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = side * half; x < side * half + 200; ++x)
        dark += picture.pixel(x, y)[0] < 100;
    EXPECT_GT(dark, 50) << "side " << side;
  }

  auto json = runCli({"compare", c1.string(), c1.string(), "--out", out.string(), "--json", "--set",
                      "membrane.derivative_constraints=false"});
  ASSERT_EQ(json.status, 0) << json.err;
  EXPECT_NE(json.out.find("\"ok\": true"), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"metrics.seam_normal_jump_mean_deg\""), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"membrane\":"), std::string::npos) << json.out;  // its seconds
  EXPECT_NE(json.out.find("\"metrics.manifold\": \"=\""), std::string::npos) << json.out;
  // The same graph twice: each side's files in a folder of its own.
  EXPECT_TRUE(std::filesystem::exists(out / "compare_mountain_sphere_membrane_a" /
                                      "compare_mountain_sphere_membrane.obj"));
  EXPECT_TRUE(std::filesystem::exists(out / "compare_mountain_sphere_membrane_b" /
                                      "compare_mountain_sphere_membrane.obj"));
}

TEST(Cli, CompareRefusesAGraphWithoutMetricsBeforeRunningEither) {
  const auto out = test::tempDir("cli-compare-bad");
  const auto measured = test::sourceDir() / "graphs" / "compare_mountain_sphere_membrane.json";
  const auto unmeasured = test::sourceDir() / "graphs" / "relief_cube.json";
  auto result = runCli({"compare", measured.string(), unmeasured.string(), "--out", out.string()});
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.errorLines(), 1) << result.err;
  EXPECT_NE(result.err.find("relief_cube.json: no geobrush.metrics node"), std::string::npos)
      << result.err;
  EXPECT_TRUE(isEmptyDir(out));
  EXPECT_EQ(runCli({"compare", measured.string(), "/no/such/graph.json"}).status, 2);
}

TEST(Cli, SetOverridesAParam) {
  const auto out = test::tempDir("cli-set");
  const auto graph = (test::sourceDir() / "graphs" / "relief_cube.json").string();
  auto small =
      runCli({"run", graph, "--out", out.string(), "--quiet", "--set", "shape.resolution=1",
              "--set", "render.width=64", "--set", "render.height=48"});
  ASSERT_EQ(small.status, 0) << small.err;
  EXPECT_TRUE(small.err.empty()) << small.err;
  auto bad = runCli({"run", graph, "--out", out.string(), "--set", "shape.resolution=-3"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("node 'shape' param 'resolution'"), std::string::npos) << bad.err;
}

TEST(Cli, ValidateAndUsageErrors) {
  EXPECT_EQ(runCli({"validate", (test::sourceDir() / "graphs" / "default.json").string()}).status,
            0);
  EXPECT_EQ(runCli({"validate", "/no/such/graph.json"}).status, 2);
  EXPECT_EQ(runCli({}).status, 2);
  EXPECT_EQ(runCli({"run"}).status, 2);
  EXPECT_EQ(runCli({"frobnicate"}).status, 2);
  EXPECT_EQ(runCli({"--help"}).status, 0);
}

TEST(Cli, RendersMeshFiles) {
  const auto dir = test::tempDir("cli-render");
  auto result = runCli({"render", test::meshPath("bunny_small.obj").string(),
                        test::meshPath("sphere.obj").string(), "-o", (dir / "two.png").string(),
                        "--width", "160", "--height", "120", "--azimuth", "45"});
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "two.png"));
  auto missing = runCli({"render", (dir / "none.obj").string(), "-o", (dir / "x.png").string()});
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.errorLines(), 1) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

// Texts from the command line are escaped as those from files are.
TEST(Cli, SetTextsAreEscapedAndBounded) {
  const auto out = test::tempDir("cli-set-escaped");
  const auto graph = (test::sourceDir() / "graphs" / "relief_cube.json").string();
  auto bad = runCli({"run", graph, "--out", out.string(), "--set",
                     "shape.shape=\x1b]0;title\x07\n" + std::string(50000, 'y')});
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(bad.errorLines(), 1) << bad.err;
  EXPECT_TRUE(test::contains(bad.err, "node 'shape' param 'shape': '\\x1b]0;title\\x07\\nyyy"));
  EXPECT_TRUE(test::contains(bad.err, "yyy... (50011 bytes)' is not one of:"));
  EXPECT_TRUE(printableBoundedLines(bad.err));
  EXPECT_LT(bad.err.size(), 1000u);
  auto noNode = runCli({"run", graph, "--out", out.string(), "--set", "sha\npe.size=1"});
  EXPECT_EQ(noNode.status, 2);
  EXPECT_TRUE(test::contains(noNode.err, "node 'sha\\npe': no node of that name"));
  EXPECT_TRUE(printableBoundedLines(noNode.err));
  EXPECT_TRUE(isEmptyDir(out));
}

// Two nodes saving one file would both report "wrote" it, and one of the meshes would be lost.
TEST(Cli, TwoOutputsToOneFileAreRefusedBeforeRunning) {
  const auto dir = test::tempDir("cli-two-saves");
  const auto out = dir / "out";
  const std::string twoSaves =
      replaced(kPrimitiveSave, R"("connections": [)",
               R"("connections": [{"from": "shape.mesh", "to": "again.mesh"}, )");
  writeText(dir / "graph.json",
            replaced(twoSaves, R"("save": {)",
                     R"("again": {"type": "geobrush.save_mesh", "typeVersion": 1,
                                  "params": {"path": "./result.obj"}}, "save": {)"));
  auto result = runCli({"run", (dir / "graph.json").string(), "--out", out.string()});
  EXPECT_EQ(result.status, 2) << result.err;
  EXPECT_EQ(result.errorLines(), 1) << result.err;
  EXPECT_TRUE(test::contains(result.err,
                             "graph.json: node 'save' param 'path': writes "
                             "'result.obj', as node 'again' param 'path' does"));
  EXPECT_TRUE(isEmptyDir(out));
  EXPECT_EQ(runCli({"validate", (dir / "graph.json").string()}).status, 2);

  // An absolute path meets a relative one in the output folder given: known only then.
  writeText(dir / "graph.json",
            replaced(twoSaves, R"("save": {)",
                     R"("again": {"type": "geobrush.save_mesh", "typeVersion": 1,
                                  "params": {"path": ")" +
                         (out / "result.obj").string() + R"("}}, "save": {)"));
  EXPECT_EQ(runCli({"validate", (dir / "graph.json").string()}).status, 0);
  auto mixed = runCli({"run", (dir / "graph.json").string(), "--out", out.string()});
  EXPECT_EQ(mixed.status, 2) << mixed.err;
  EXPECT_TRUE(test::contains(mixed.err, "node 'save' param 'path': writes " +
                                            test::quoted(out / "result.obj") +
                                            ", as node 'again' param 'path' does"));
  EXPECT_TRUE(isEmptyDir(out));
  // --set can make the collision too.
  auto set = runCli({"run", (dir / "graph.json").string(), "--out", (dir / "other").string(),
                     "--set", "save.path=" + (dir / "other" / "x" / ".." / "result.obj").string(),
                     "--set", "again.path=result.obj"});
  EXPECT_EQ(set.status, 2) << set.err;
  EXPECT_TRUE(isEmptyDir(dir / "other"));
}

// Devices and pipes have no size: the file is read through the stream, and at most 64 MiB of it.
TEST(Cli, RefusesAGraphFileOver64MiBAndReadsOneFromAPipe) {
  const auto dir = test::tempDir("cli-graph-size");
  const auto huge = dir / "huge.json";
  writeText(huge, kPrimitiveSave);
  std::filesystem::resize_file(huge, (std::size_t(64) << 20) + 1);  // sparse: nothing written
  auto result = runCli({"run", huge.string(), "--out", (dir / "out").string()});
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.errorLines(), 1) << result.err;
  EXPECT_TRUE(test::contains(result.err, huge.string() + ": larger than 64 MiB"));
  EXPECT_TRUE(isEmptyDir(dir / "out"));

  const auto fifo = dir / "piped.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo) << kPrimitiveSave; });
  auto piped = runCli({"validate", fifo.string()});
  writer.join();
  EXPECT_EQ(piped.status, 0) << piped.err;
}

// The render command checks its options as the render node checks its params (the ranges are
// render.hpp's), each error naming the option; its image is a PNG, named so.
TEST(Cli, RenderFramesAFocus) {
  const auto dir = test::tempDir("cli-render-focus");
  const auto sphere = test::meshPath("sphere.obj").string();
  const auto framed =
      runCli({"render", sphere, "-o", (dir / "a.png").string(), "--backend", "cpu", "--azimuth",
              "0", "--elevation", "0", "--focus", "0,0,1", "--focus-radius", "0.1"});
  ASSERT_EQ(framed.status, 0) << framed.err;
  const Image image = readPng(dir / "a.png");
  for (int y = 0; y < image.height; y += 7)
    for (int x = 0; x < image.width; x += 7)
      ASSERT_NE(image.pixel(x, y)[0], 255) << "background at " << x << ", " << y;

  const auto alone =
      runCli({"render", sphere, "-o", (dir / "b.png").string(), "--focus-radius", "1"});
  EXPECT_EQ(alone.status, 2);
  EXPECT_TRUE(test::contains(alone.err, "--focus-radius needs --focus"));
  EXPECT_FALSE(std::filesystem::exists(dir / "b.png"));
}

TEST(Cli, RenderOptionErrorsNameTheOption) {
  const auto dir = test::tempDir("cli-render-options");
  const std::string mesh = test::meshPath("sphere.obj").string();
  const std::string png = (dir / "x.png").string();
  const std::vector<std::vector<std::string>> bad = {
      {"--zoom", "1e400"},  {"--zoom", "0"},      {"--zoom", "abc"},    {"--width", "0"},
      {"--width", "16.5"},  {"--height", "9000"}, {"--fov", "nan"},     {"--fov", "170"},
      {"--azimuth", "inf"}, {"--azimuth", "400"}, {"--elevation", "90"}};
  for (const auto& option : bad) {
    auto result = runCli({"render", mesh, "-o", png, option[0], option[1]});
    EXPECT_EQ(result.status, 2) << option[0] << " " << option[1] << ": " << result.err;
    EXPECT_EQ(result.errorLines(), 1) << result.err;
    EXPECT_TRUE(test::contains(result.err, "error: " + option[0] + ": ")) << option[1];
    EXPECT_TRUE(printableBoundedLines(result.err));
  }
  auto range = runCli({"render", mesh, "-o", png, "--width", "8"});
  EXPECT_TRUE(test::contains(range.err, "error: --width: 8 is outside [" +
                                            formatParam(kRenderSizeRange.min) + ", " +
                                            formatParam(kRenderSizeRange.max) + "]"));
  for (const char* name : {"x.jpg", "x.png.txt", "x"}) {
    auto result = runCli({"render", mesh, "-o", (dir / name).string()});
    EXPECT_EQ(result.status, 2) << name;
    EXPECT_EQ(result.errorLines(), 1) << result.err;
    EXPECT_TRUE(test::contains(result.err, "error: --output: " + test::quoted(dir / name)));
  }
  EXPECT_TRUE(isEmptyDir(dir));
  // Any letter case names a PNG; the ranges' ends are inside.
  auto upper = runCli({"render", mesh, "-o", (dir / "X.PNG").string(), "--width", "16", "--height",
                       "16", "--zoom", "50", "--fov", "5", "--elevation", "-89"});
  EXPECT_EQ(upper.status, 0) << upper.err;
  EXPECT_EQ(readPng(dir / "X.PNG").width, 16);
}

// An existing output must be a regular file, or a link to one (written through: the link stays).
TEST(Cli, NeverReplacesADeviceFifoOrFolder) {
  const auto dir = test::tempDir("cli-special-outputs");
  const std::string mesh = test::meshPath("sphere.obj").string();
  const auto fifo = dir / "fifo.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::filesystem::create_directory(dir / "folder.png");
  std::filesystem::create_symlink("fifo.png", dir / "to_fifo.png");
  for (const char* name : {"fifo.png", "folder.png", "to_fifo.png"}) {
    auto result = runCli({"render", mesh, "-o", (dir / name).string(), "--width", "32"});
    EXPECT_EQ(result.status, 1) << name;
    EXPECT_EQ(result.errorLines(), 1) << result.err;
    EXPECT_TRUE(test::contains(result.err, "error: " + test::quoted(dir / name) + ": "));
  }
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_TRUE(std::filesystem::is_directory(dir / "folder.png"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "to_fifo.png"));

  // geobrush.save_mesh in a graph: the node fails, naming its param; nothing is written.
  writeText(dir / "graph.json", kPrimitiveSave);
  const auto fifoObj = dir / "fifo.obj";
  ASSERT_EQ(::mkfifo(fifoObj.c_str(), 0600), 0);
  auto run = runCli({"run", (dir / "graph.json").string(), "--set", "save.path=fifo.obj"});
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_EQ(run.errorLines(), 1) << run.err;
  EXPECT_TRUE(test::contains(
      run.err, "graph.json: node 'save' param 'path': " + test::quoted(fifoObj) + ": is a FIFO"));
  EXPECT_TRUE(std::filesystem::is_fifo(fifoObj));
  EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"fifo.obj", "fifo.png", "folder.png",
                                                    "graph.json", "to_fifo.png"}));
}

TEST(Cli, WritesThroughASymlinkToARegularFile) {
  const auto dir = test::tempDir("cli-symlink-output");
  std::filesystem::create_directories(dir / "real");
  std::filesystem::create_directories(dir / "out");
  writeText(dir / "real" / "picture.png", "old");
  writeText(dir / "real" / "mesh.obj", "old");
  std::filesystem::create_symlink("../real/picture.png", dir / "out" / "picture.png");
  std::filesystem::create_symlink(dir / "real" / "mesh.obj", dir / "out" / "mesh.obj");

  auto render = runCli({"render", test::meshPath("sphere.obj").string(), "-o",
                        (dir / "out" / "picture.png").string(), "--width", "32", "--height", "24"});
  ASSERT_EQ(render.status, 0) << render.err;
  writeText(dir / "graph.json", kPrimitiveSave);
  auto run = runCli({"run", (dir / "graph.json").string(), "--out", (dir / "out").string(), "--set",
                     "save.path=mesh.obj", "--set", "shape.resolution=2"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(test::contains(run.err, "wrote " + (dir / "out" / "mesh.obj").string()));

  // The links stay; the files they lead to are replaced, and no temporary file is left anywhere.
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "out" / "picture.png"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "out" / "mesh.obj"));
  EXPECT_EQ(readPng(dir / "real" / "picture.png").width, 32);
  EXPECT_GT(std::filesystem::file_size(dir / "real" / "mesh.obj"), 100u);
  EXPECT_EQ(namesIn(dir / "out"), (std::vector<std::string>{"mesh.obj", "picture.png"}));
  EXPECT_EQ(namesIn(dir / "real"), (std::vector<std::string>{"mesh.obj", "picture.png"}));
}
