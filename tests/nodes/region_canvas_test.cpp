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

// The region R_in of the source canvas vertices whose uv passes `inside`.
Region2D regionWhere(const Parameterization& source,
                     const std::function<bool(const Eigen::Vector2d&)>& inside) {
  Region2D region;
  for (std::size_t v = 0; v < source.uv.size(); ++v)
    if (inside(source.uv[v])) region.sourceVertices.push_back(int(v));
  return region;
}

// Faces of the source canvas with three corners in the region.
std::size_t wholeFaces(const Parameterization& source, const Region2D& region) {
  std::vector<char> in(source.uv.size(), 0);
  for (int v : region.sourceVertices)
    in[std::size_t(v)] = 1;
  std::size_t count = 0;
  for (auto f : source.canvas->surface.faces()) {
    bool all = true;
    for (auto v : source.canvas->surface.fv_range(f))
      all = all && in[std::size_t(v.idx())];
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
  const Region2D disc =
      regionWhere(*source, [](const Eigen::Vector2d& u) { return u.norm() < 0.6; });
  const RegionCanvasResult result = regionCanvas(disc, *source);
  expectDisc(result.feature.surface);
  EXPECT_EQ(result.feature.surface.n_faces(), wholeFaces(*source, disc));
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
  const Region2D painted = regionWhere(*source, [](const Eigen::Vector2d& u) {
    const double r = (u - Eigen::Vector2d(0.01, 0.02)).norm();
    const bool ring = r > 0.25 && r < 0.6;
    const bool apart = (u - Eigen::Vector2d(0.85, 0.85)).norm() < 0.12;
    return ring || apart;
  });
  const RegionCanvasResult result = regionCanvas(painted, *source);
  expectDisc(result.feature.surface);
  EXPECT_GT(result.enclosed, 0u);
  EXPECT_GT(result.dropped, 0u);
  const Region2D disc = regionWhere(*source, [](const Eigen::Vector2d& u) {
    return (u - Eigen::Vector2d(0.01, 0.02)).norm() < 0.6;
  });
  EXPECT_EQ(result.feature.surface.n_faces(), wholeFaces(*source, disc));
}

TEST(RegionCanvas, ARegionOnARealTerrainIsADisc) {
  const auto terrain =
      wholeMesh(readMesh(test::meshPath("mountain.obj")).mesh,
                [](const TriMesh::Point& p) { return Eigen::Vector2d(p[0], -p[2]); });
  double reach = 0;
  for (const auto& u : terrain->uv)
    reach = std::max(reach, u.norm());
  const Region2D region =
      regionWhere(*terrain, [&](const Eigen::Vector2d& u) { return u.norm() < 0.3 * reach; });
  const RegionCanvasResult result = regionCanvas(region, *terrain);
  expectDisc(result.feature.surface);
  EXPECT_EQ(result.feature.surface.n_faces(), wholeFaces(*terrain, region) + result.enclosed);
}

TEST(RegionCanvasNode, OutputsTheFeatureAndNamesAnEmptyRegion) {
  const auto source = heightField(12, [](double, double) { return 0.0; });
  const NodeType* type = test::registry().find("geobrush.region_canvas");
  ASSERT_NE(type, nullptr);
  auto disc = std::make_shared<const Region2D>(
      regionWhere(*source, [](const Eigen::Vector2d& u) { return u.norm() < 0.5; }));
  test::DirectContext ctx(*type, {{"region", disc}, {"source", source}});
  test::run(type->create(), ctx);
  const auto feature = std::dynamic_pointer_cast<const Canvas>(ctx.outputs.at("feature"));
  ASSERT_NE(feature, nullptr);
  expectDisc(feature->surface);

  auto empty = std::make_shared<const Region2D>();
  test::DirectContext bad(*type, {{"region", empty}, {"source", source}});
  try {
    test::run(type->create(), bad);
    FAIL() << "an empty region gave a canvas";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'region'");
  }
}

}  // namespace
}  // namespace geobrush
