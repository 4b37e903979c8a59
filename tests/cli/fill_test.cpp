// `geobrush fill`: a mesh's holes filled from plain arguments, with the command line's contract.
#include <gtest/gtest.h>

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

TEST(CliFill, ALoopItCannotFillFailsByNameAndWritesNothing) {
  const fs::path dir = test::tempDir("cli_fill_fail");
  const auto run = runCli({"fill", test::meshPath("mech_holes_shark.obj").string(), "-o",
                           (dir / "shark.obj").string()});
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.errorLines(), 1) << run.err;
  EXPECT_TRUE(test::contains(run.err, "mech_holes_shark.obj: node 'fill'"));
  EXPECT_TRUE(test::contains(run.err, "loop 0 (96 border edges, from vertex 0)"));
  EXPECT_FALSE(fs::exists(dir / "shark.obj"));
  // The other loops fill when chosen.
  const auto others = runCli({"fill", test::meshPath("mech_holes_shark.obj").string(), "-o",
                              (dir / "shark.obj").string(), "--holes", "1,2,3"});
  EXPECT_EQ(others.status, 0) << others.err;
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
