// `geobrush fill`: a mesh's holes filled from plain arguments, with the command line's contract.
#include <gtest/gtest.h>

#include <array>
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
  EXPECT_TRUE(test::contains(run.out, "\"holes\": ["));
  EXPECT_TRUE(test::contains(run.out, "\"border_edges\": 80,"));
  EXPECT_TRUE(test::contains(run.out, "\"filled\": false,"));
  EXPECT_TRUE(test::contains(run.out, "\"new_vertices\": "));
  EXPECT_TRUE(test::contains(run.out, "\"time_ms\": "));
  EXPECT_TRUE(test::contains(run.out, "loop 4 left open: the largest loop"));
  EXPECT_EQ(test::topology(readMesh(dir / "bunny.obj").mesh->surface).boundaryLoops, 1u);
}

// A square sheet with a round hole and a pin standing through it: any disc spanning the hole
// cuts the pin.
fs::path pinThroughHole(const fs::path& dir) {
  std::string obj;
  const int n = 10;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      obj += "v " + std::to_string(double(i) / n) + " " + std::to_string(double(j) / n) + " 0\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (std::hypot((i + 0.5) / n - 0.5, (j + 0.5) / n - 0.5) < 0.25) continue;
      const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
      obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  const int base = (n + 1) * (n + 1);
  obj += "v 0.45 0.45 -0.5\nv 0.55 0.45 -0.5\nv 0.5 0.55 -0.5\nv 0.5 0.5 0.5\n";
  for (const auto& f :
       {std::array{1, 3, 2}, std::array{1, 2, 4}, std::array{2, 3, 4}, std::array{3, 1, 4}})
    obj += "f " + std::to_string(base + f[0]) + " " + std::to_string(base + f[1]) + " " +
           std::to_string(base + f[2]) + "\n";
  return test::writeFile(dir / "pinned.obj", obj);
}

TEST(CliFill, ALoopItCannotFillFailsByNameAndWritesNothing) {
  const fs::path dir = test::tempDir("cli_fill_fail");
  const auto run = runCli({"fill", pinThroughHole(dir).string(), "-o", (dir / "out.obj").string(),
                           "--holes", "all-but-largest", "--image", (dir / "out.png").string()});
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.errorLines(), 1) << run.err;
  EXPECT_TRUE(test::contains(run.err, "pinned.obj: node 'fill'"));
  EXPECT_TRUE(test::contains(run.err, "its fill would cut through the surface"));
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
