// geobrush.roi_correct: outlines that cut folded or protruding faces take them in whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "geobrush/exponential_map.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/surface_point.hpp"
#include "roi_correct.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

Strokes strokes(std::vector<Dab> dabs) {
  Strokes s;
  s.dabs = std::move(dabs);
  return s;
}

// A tall narrow spike on a plane, parameterized by projection (DEM normals +z): its flanks turn
// almost vertical.
std::shared_ptr<Parameterization> spike() {
  return test::heightFieldParameterization(60, [](double x, double y) {
    return 2.0 * std::exp(-((x - 0.3) * (x - 0.3) + y * y) / 0.02);
  });
}

// Vertices of the spike's steep part: where the surface rises above a tenth of its height.
std::vector<int> spikeVertices(const Parameterization& param) {
  std::vector<int> vertices;
  for (auto v : param.canvas->surface.vertices())
    if (param.canvas->surface.point(v)[2] > 0.2) vertices.push_back(v.idx());
  return vertices;
}

}  // namespace

TEST(RoiCorrect, PaintingPartOfASpikeTakesAllOfIt) {
  auto param = spike();
  RoiCorrectOptions options;
  options.includeProtrusions = true;
  // The dab covers the spike's left half only.
  const Strokes painted = strokes({{{0.0, 0.0}, 0.32, false}});
  std::size_t before = 0;
  for (int v : spikeVertices(*param))
    before += painted.contains(param->uv[std::size_t(v)]);
  ASSERT_GT(before, 0u);
  ASSERT_LT(before, spikeVertices(*param).size());

  const RoiCorrectResult result = correctRoi(painted, *param, options);
  EXPECT_TRUE(result.settled);
  EXPECT_EQ(result.featuresAdded, 1u);
  ASSERT_EQ(result.strokes.dabs.size(), 2u);
  for (int v : spikeVertices(*param))
    EXPECT_TRUE(result.strokes.contains(param->uv[std::size_t(v)])) << v;
  // The added disc stays near the spike: the far side of the plane is not taken.
  EXPECT_FALSE(result.strokes.contains({0.9, 0.0}));

  // With the flags computed once, as the node keeps them while a brush paints: the same dabs.
  const auto flags = correctionFlags(*param, options);
  EXPECT_EQ(correctRoi(painted, *param, options, flags).strokes.dabs, result.strokes.dabs);
  EXPECT_THROW(correctRoi(painted, *param, options, std::vector<std::uint8_t>(3, 1)),
               RoiCorrectError);
}

TEST(RoiCorrect, LeavesOutlinesThatCutNoFlaggedFace) {
  auto param = spike();
  RoiCorrectOptions options;
  options.includeProtrusions = true;
  for (const Strokes& s :
       {strokes({{{-0.7, 0}, 0.2, false}}), strokes({{{0.3, 0}, 0.6, false}}), Strokes()}) {
    const RoiCorrectResult result = correctRoi(s, *param, options);
    EXPECT_EQ(result.strokes.dabs, s.dabs);
    EXPECT_EQ(result.featuresAdded, 0u);
  }
}

// Without protrusions only the map's reversed flags count: a flagged patch cut by the outline is
// taken in, through its flagged neighbours, and an unflagged spike is not.
TEST(RoiCorrect, GrowsThroughAdjacentReversedFaces) {
  auto param = spike();
  auto flagged = std::make_shared<Parameterization>(*param);
  const TriMesh& mesh = param->canvas->surface;
  flagged->reversedFaces.assign(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (auto v : mesh.fv_range(f))
      centre += param->uv[std::size_t(v.idx())] / 3;
    flagged->reversedFaces[std::size_t(f.idx())] =
        (centre - Eigen::Vector2d(-0.5, -0.5)).norm() < 0.2;
  }
  const Strokes cut = strokes({{{-0.5, -0.7}, 0.25, false}, {{0.0, 0.0}, 0.32, false}});
  const RoiCorrectResult result = correctRoi(cut, *flagged, RoiCorrectOptions{});
  EXPECT_EQ(result.featuresAdded, 1u);
  for (auto f : mesh.faces()) {
    if (!flagged->reversedFaces[std::size_t(f.idx())]) continue;
    for (auto v : mesh.fv_range(f))
      EXPECT_TRUE(result.strokes.contains(param->uv[std::size_t(v.idx())]));
  }
  // The spike is cut by the second dab but is not flagged in this mode.
  EXPECT_FALSE(result.strokes.contains({0.45, 0.0}));
  EXPECT_TRUE(result.outlineFaces.empty());
}

// A flagged patch that reaches the canvas' outline: the correction takes it in and names the
// faces at the outline, where the region ends inside folded geometry.
TEST(RoiCorrect, NamesTheFacesItTakesInAtTheCanvasOutline) {
  auto param = spike();
  auto flagged = std::make_shared<Parameterization>(*param);
  const TriMesh& mesh = param->canvas->surface;
  flagged->reversedFaces.assign(mesh.n_faces(), 0);
  double left = 0.0;
  for (auto v : mesh.vertices())
    left = std::min(left, param->uv[std::size_t(v.idx())].x());
  for (auto f : mesh.faces()) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (auto v : mesh.fv_range(f))
      centre += param->uv[std::size_t(v.idx())] / 3;
    flagged->reversedFaces[std::size_t(f.idx())] =
        (centre - Eigen::Vector2d(left, 0.0)).norm() < 0.2;
  }
  const RoiCorrectResult result =
      correctRoi(strokes({{{left + 0.25, 0.0}, 0.2, false}}), *flagged, RoiCorrectOptions{});
  EXPECT_EQ(result.featuresAdded, 1u);
  ASSERT_FALSE(result.outlineFaces.empty());
  for (int f : result.outlineFaces) {
    EXPECT_TRUE(flagged->reversedFaces[std::size_t(f)]);
    bool atOutline = false;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      atOutline = atOutline || mesh.is_boundary(v);
    EXPECT_TRUE(atOutline) << f;
  }
}

// On a real canvas the correction leaves no flagged face cut, whatever the dab.
TEST(RoiCorrect, LeavesNoCutFeatureOnARealMesh) {
  const MeshPtr armadillo = readMesh(test::meshPath("armadillo.obj")).mesh;
  // The ear, as graphs/preprocess_armadillo_ear.json paints it.
  const int earFace = nearestSurfacePoint(armadillo->surface, {0.102853, 0.375548, 0.167421}).face;
  auto canvas = std::make_shared<Canvas>(test::growDiscCanvas(armadillo, earFace, 0.1));
  DemOptions demOptions;
  DemResult dem = discreteExponentialMap(*canvas, demOptions);
  auto param = std::make_shared<Parameterization>();
  param->canvas = canvas;
  param->uv = std::move(dem.uv);
  param->normal = std::move(dem.normal);
  param->reversedFaces = std::move(dem.reversedFaces);
  RoiCorrectOptions options;
  options.includeProtrusions = true;
  std::size_t corrected = 0;
  for (double radius : {0.02, 0.05}) {
    const RoiCorrectResult result =
        correctRoi(strokes({{{0.01, 0.02}, radius, false}}), *param, options);
    EXPECT_TRUE(result.settled);
    corrected += result.featuresAdded;
    const auto flags =
        growFaceRing(canvas->surface, reversedFaces(canvas->surface, param->normal, 0.5), 3);
    for (auto f : canvas->surface.faces()) {
      if (!flags[std::size_t(f.idx())]) continue;
      int inside = 0;
      for (auto v : canvas->surface.fv_range(f))
        inside += result.strokes.contains(param->uv[std::size_t(v.idx())]);
      EXPECT_TRUE(inside == 0 || inside == 3) << "face " << f.idx() << ", radius " << radius;
    }
  }
  EXPECT_GT(corrected, 0u);  // the ear's folds were cut and taken in
}

TEST(RoiCorrect, RefusesFlagsOfAnotherCanvas) {
  auto param = std::make_shared<Parameterization>(*spike());
  param->reversedFaces.assign(3, 1);
  EXPECT_THROW(correctRoi(strokes({{{0, 0}, 0.5, false}}), *param), RoiCorrectError);
}
