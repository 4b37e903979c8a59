#include "region_canvas.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/cut_paste.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// The whole mesh as a source canvas, parameterized by `uv` of its points.
ParameterizationPtr wholeMesh(const MeshPtr& mesh,
                              const std::function<Eigen::Vector2d(const TriMesh::Point&)>& uv) {
  std::vector<int> faces(mesh->surface.n_faces());
  for (std::size_t f = 0; f < faces.size(); ++f)
    faces[f] = int(f);
  auto canvas = std::make_shared<const Canvas>(canvasFromFaces(
      mesh, faces, 0, Eigen::Vector3d(mesh->surface.point(TriMesh::VertexHandle(0)).data())));
  auto p = std::make_shared<Parameterization>();
  p->canvas = canvas;
  for (auto v : canvas->surface.vertices()) {
    p->uv.push_back(uv(canvas->surface.point(v)));
    p->normal.push_back(Eigen::Vector3d::UnitZ());
  }
  return p;
}

ParameterizationPtr heightField(int n, const std::function<double(double, double)>& height) {
  return wholeMesh(test::heightGrid(n, height),
                   [](const TriMesh::Point& p) { return Eigen::Vector2d(p[0], p[1]); });
}

Strokes disc(const Eigen::Vector2d& centre, double radius, bool subtract = false) {
  Strokes strokes;
  strokes.dabs.push_back(Dab{centre, radius, subtract});
  return strokes;
}

// Faces of the source canvas whose three corners the strokes paint.
std::size_t paintedFaces(const Parameterization& source, const Strokes& strokes) {
  std::size_t count = 0;
  for (auto f : source.canvas->surface.faces()) {
    bool all = true;
    for (auto v : source.canvas->surface.fv_range(f))
      all = all && strokes.contains(source.uv[std::size_t(v.idx())]);
    count += all;
  }
  return count;
}

void expectDisc(const TriMesh& surface) {
  const auto shape = test::topology(surface);
  EXPECT_EQ(shape.boundaryLoops, 1u);
  EXPECT_EQ(shape.components, 1u);
  EXPECT_EQ(shape.nonManifoldVertices, 0u);
}

TEST(RegionCanvas, APaintedDiscIsItsWholeFacesOnTheSourceMesh) {
  const auto source =
      heightField(20, [](double x, double y) { return 0.1 * std::sin(3 * x) * std::cos(2 * y); });
  const Strokes painted = disc({0, 0}, 0.6);
  const RegionCanvasResult result = regionCanvas(painted, *source);
  expectDisc(result.feature.surface);
  EXPECT_EQ(result.feature.surface.n_faces(), paintedFaces(*source, painted));
  EXPECT_EQ(result.dropped, 0u);
  EXPECT_EQ(result.enclosed, 0u);
  EXPECT_EQ(result.feature.source, source->canvas->source);
  // Its faces are the source mesh's own, in place.
  for (auto v : result.feature.surface.vertices()) {
    const int s = result.feature.sourceVertex[std::size_t(v.idx())];
    EXPECT_EQ(result.feature.surface.point(v),
              source->canvas->source->surface.point(TriMesh::VertexHandle(s)));
  }
}

TEST(RegionCanvas, ARingTakesInWhatItEnclosesAndAPieceApartIsLeftOut) {
  const auto source = heightField(24, [](double, double) { return 0.0; });
  const Eigen::Vector2d centre(0.01, 0.02);
  Strokes painted = disc(centre, 0.6);
  painted.dabs.push_back(Dab{centre, 0.25, true});
  painted.dabs.push_back(Dab{{0.85, 0.85}, 0.12, false});
  const RegionCanvasResult result = regionCanvas(painted, *source);
  expectDisc(result.feature.surface);
  EXPECT_GT(result.enclosed, 0u);
  EXPECT_GT(result.dropped, 0u);
  EXPECT_EQ(result.feature.surface.n_faces(), paintedFaces(*source, disc(centre, 0.6)));
}

TEST(RegionCanvas, ARegionOnARealTerrainIsADisc) {
  const auto terrain =
      wholeMesh(readMesh(test::meshPath("mountain.obj")).mesh,
                [](const TriMesh::Point& p) { return Eigen::Vector2d(p[0], -p[2]); });
  double reach = 0;
  for (const auto& u : terrain->uv)
    reach = std::max(reach, u.norm());
  const Strokes painted = disc({0, 0}, 0.3 * reach);
  const RegionCanvasResult result = regionCanvas(painted, *terrain);
  expectDisc(result.feature.surface);
  EXPECT_EQ(result.feature.surface.n_faces(), paintedFaces(*terrain, painted) + result.enclosed);
}

TEST(RegionCanvasNode, OutputsTheFeatureAndNamesAnEmptyPainting) {
  const auto source = heightField(12, [](double, double) { return 0.0; });
  const NodeType* type = test::registry().find("geobrush.region_canvas");
  ASSERT_NE(type, nullptr);
  auto painted = std::make_shared<const Strokes>(disc({0, 0}, 0.5));
  test::DirectContext ctx(*type, {{"strokes", painted}, {"source", source}});
  test::run(type->create(), ctx);
  const auto feature = std::dynamic_pointer_cast<const Canvas>(ctx.outputs.at("feature"));
  ASSERT_NE(feature, nullptr);
  expectDisc(feature->surface);

  auto empty = std::make_shared<const Strokes>();
  test::DirectContext bad(*type, {{"strokes", empty}, {"source", source}});
  try {
    test::run(type->create(), bad);
    FAIL() << "an empty painting gave a canvas";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'strokes'");
  }
}

}  // namespace
}  // namespace geobrush
