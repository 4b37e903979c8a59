// fill_holes against CGAL 5.5: the exact self-intersection test on every fill of the shared
// meshes, and the distance of each cut hole's fill to the removed patch next to CGAL's
// triangulate_refine_and_fair_hole (C1, density sqrt 2) on the same hole.
#include <gtest/gtest.h>

#include <string>

#include <Eigen/Geometry>
#include <vector>

#include "cgal_reference.hpp"
#include "fill_holes.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

TriMesh load(const std::filesystem::path& path) {
  return readMesh(path).mesh->surface;
}

std::vector<Eigen::Vector3d> addedPoints(const TriMesh& filled, const TriMesh& holed) {
  std::vector<Eigen::Vector3d> points;
  for (auto v : filled.vertices()) {
    if (v.idx() < int(holed.n_vertices())) continue;
    const auto& p = filled.point(v);
    points.emplace_back(p[0], p[1], p[2]);
  }
  return points;
}

TEST(FillHolesAgainstCgal, TheScansAndTheCadPartFillWithoutSelfIntersections) {
  const TriMesh bunny = load(test::meshPath("bunny_scan.obj"));
  EXPECT_EQ(test::cgalSelfIntersections(fillHoles(bunny, {}).mesh), 0u);
  const TriMesh shark = load(test::meshPath("mech_holes_shark.obj"));
  EXPECT_EQ(test::cgalSelfIntersections(fillHoles(shark, {}).mesh), 0u);
}

class CutHoleAgainstCgal : public ::testing::TestWithParam<const char*> {};

TEST_P(CutHoleAgainstCgal, FillsAtLeastAsNearTheRemovedPatchWithoutSelfIntersections) {
  const std::string name = GetParam();
  const TriMesh holed = load(test::meshDir() / "cases" / (name + "_hole.obj"));
  const TriMesh truth = load(test::meshDir() / "cases" / (name + "_removed_patch.obj"));
  const auto ours = fillHoles(holed, {});
  EXPECT_EQ(test::cgalSelfIntersections(ours.mesh), 0u);
  const auto cgal = test::cgalFillHoles(holed, 1);
  const double diag = boundingDiagonal(holed);
  const auto oursDistance = test::cgalDistances(addedPoints(ours.mesh, holed), truth);
  const auto cgalDistance = test::cgalDistances(addedPoints(cgal.mesh, holed), truth);
  RecordProperty("mean_over_diag", std::to_string(oursDistance.mean / diag));
  RecordProperty("cgal_mean_over_diag", std::to_string(cgalDistance.mean / diag));
  EXPECT_LE(oursDistance.mean, cgalDistance.mean);
  // The holes' radii are 4-8% of the diagonal: a fill that missed the surface's curvature would
  // be off by a good part of that.
  EXPECT_LT(oursDistance.max, 0.01 * diag);
}

INSTANTIATE_TEST_SUITE_P(Cases, CutHoleAgainstCgal,
                         ::testing::Values("bunny_small_back", "nefertiti_forehead",
                                           "nefertiti_back"));

}  // namespace
}  // namespace geobrush
