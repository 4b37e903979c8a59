// `geobrush fill`: a mesh's holes filled from plain arguments, with the command line's contract.
#include <gtest/gtest.h>

#include <cmath>

#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "process.hpp"
#include "test_support.hpp"

using namespace geobrush;
using test::runCli;

namespace {

namespace fs = std::filesystem;

TEST(CliFill, ClosesEveryHoleOfAScanAndSaysWhatItAdded) {
  const fs::path dir = test::tempDir("cli_fill");
  const auto run = runCli({"fill", test::meshPath("bunny_scan.obj").string(), "-o",
                           (dir / "bunny.obj").string(), "--image", (dir / "bunny.png").string()});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(test::contains(run.err, "loop 4: 80 border edges, filled with"));
  const auto filled = readMesh(dir / "bunny.obj").mesh->surface;
  EXPECT_EQ(test::topology(filled).boundaryLoops, 0u);
  EXPECT_TRUE(fs::exists(dir / "bunny.png"));
}

TEST(CliFill, LeavesTheLargestLoopOpenAndReportsEachLoopAsJson) {
  const fs::path dir = test::tempDir("cli_fill_json");
  const auto run = runCli({"fill", test::meshPath("bunny_scan.obj").string(), "-o",
                           (dir / "bunny.obj").string(), "--holes", "all-but-largest", "--json"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(test::contains(run.out, "\"fill.loop.4.filled\": 0.0"));
  EXPECT_TRUE(test::contains(run.out, "\"fill.loop.0.new_vertices\""));
  EXPECT_TRUE(test::contains(run.out, "\"fill.loop.0.time_ms\""));
  EXPECT_EQ(test::topology(readMesh(dir / "bunny.obj").mesh->surface).boundaryLoops, 1u);
}

// A strip wound one and a half times around an axis: the disc spanning its border cuts it.
fs::path helicalStrip(const fs::path& dir) {
  std::string obj;
  const int n = 90;
  for (int i = 0; i <= n; ++i) {
    const double angle = 3.0 * M_PI * i / n;
    for (double w : {0.0, 0.3})
      obj += "v " + std::to_string(std::cos(angle)) + " " + std::to_string(std::sin(angle)) + " " +
             std::to_string(0.1 * angle + w) + "\n";
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i + 1, b = a + 1, c = a + 2, d = a + 3;
    obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    obj += "f " + std::to_string(a) + " " + std::to_string(d) + " " + std::to_string(b) + "\n";
  }
  return test::writeFile(dir / "strip.obj", obj);
}

TEST(CliFill, ALoopItCannotFillFailsByNameAndWritesNothing) {
  const fs::path dir = test::tempDir("cli_fill_fail");
  const auto run = runCli({"fill", helicalStrip(dir).string(), "-o", (dir / "out.obj").string(),
                           "--image", (dir / "out.png").string()});
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.errorLines(), 1) << run.err;
  EXPECT_TRUE(test::contains(run.err, "strip.obj: node 'fill'"));
  EXPECT_TRUE(test::contains(run.err, "loop 0 (182 border edges, from vertex 0)"));
  EXPECT_FALSE(fs::exists(dir / "out.obj"));
  EXPECT_FALSE(fs::exists(dir / "out.png"));
}

TEST(CliFill, BadArgumentsExitTwoWithOneLine) {
  const fs::path dir = test::tempDir("cli_fill_bad");
  const std::string mesh = test::meshPath("bunny_scan.obj").string();
  const std::string out = (dir / "out.obj").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"fill", mesh, "-o", out, "--holes", "1,,2"},
        {"fill", mesh, "-o", out, "--holes", "largest"},
        {"fill", mesh, "-o", out, "--continuity", "2"},
        {"fill", mesh}}) {
    const auto run = runCli(args);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(run.errorLines(), 1) << run.err;
  }
  const auto missing = runCli({"fill", mesh, "-o", out, "--holes", "9"});
  EXPECT_EQ(missing.status, 1);
  EXPECT_TRUE(test::contains(missing.err, "there is no loop 9 (the mesh has 5 boundary loops)"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
