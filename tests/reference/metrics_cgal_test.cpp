// geobrush.metrics counts new self-intersections as CGAL's exact test does, on pastes that have
// them: faces sharing a vertex that meet beyond it count, as do faces apart that meet.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cgal_reference.hpp"
#include "geobrush/mesh_io.hpp"
#include "process.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;

// The count `geobrush clone` prints for metrics.new_self_intersections, or -1.
double printedCount(const std::string& err) {
  const std::string key = "metrics.new_self_intersections = ";
  const auto at = err.find(key);
  return at == std::string::npos ? -1.0 : std::stod(err.substr(at + key.size()));
}

void expectMetricsCountLikeCgal(std::vector<std::string> args, const fs::path& output) {
  args.insert(args.end(), {"-o", output.string(), "--set", "metrics.require_valid=false"});
  const auto run = test::runCli(args);
  ASSERT_EQ(run.status, 0) << run.err;
  const double count = printedCount(run.err);
  EXPECT_GT(count, 0.0) << run.err;
  EXPECT_EQ(count, double(test::cgalSelfIntersections(readMesh(output).mesh->surface)));
}

TEST(MetricsAgainstCgal, CountsTheSelfIntersectionsOfFoldedPastesAlike) {
  const fs::path dir = test::tempDir("metrics-cgal");
  // The mountain onto the tip of bunny_small's ear: the paste cuts through the ear.
  expectMetricsCountLikeCgal({"clone", "--source", test::meshPath("mountain.obj").string(),
                              "--source-point", "0.068548,19.73209,0.029055", "--radius", "6",
                              "--target", test::meshPath("bunny_small.obj").string(),
                              "--target-point", "-0.479417,9.43959,-0.676324", "--scale", "0.1313"},
                             dir / "ear_tip.obj");
  // The boot's lacing: the seam folds against a cut lace at the collar.
  expectMetricsCountLikeCgal(
      {"clone", "--source", test::meshPath("boot.obj").string(), "--source-point",
       "0.01837,0.11851,0.00119", "--radius", "0.03", "--target",
       test::meshPath("sphere.obj").string(), "--target-point", "0,0,1", "--scale", "8", "--set",
       "source_canvas.dabs=0.01837,0.11851,0.00119,0.08", "--set", "source_map.reversed_ring=1",
       "--set", "target_map.margin=0.5"},
      dir / "boot.obj");
}

}  // namespace
}  // namespace geobrush
