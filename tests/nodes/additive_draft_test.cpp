#include "additive_draft.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "emd_fixtures.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

double bump(double x, double y) {
  return 0.3 * std::exp(-6 * (x * x + y * y));
}

// A bump on a plane added to a flat target: the draft is the bump itself (its base is the plane
// under it); to a tilted plane at half scale, the bump at half size along the tilted normal.
TEST(AdditiveDraft, AddsTheSourcesBumpAlongTheTargetsNormal) {
  const auto source = test::projectedParameterization(test::heightGrid(20, bump), Vector3d::UnitX(),
                                                      Vector3d::UnitY());
  const MeshPtr flat = test::heightGrid(20, [](double, double) { return 0.0; });
  const auto onFlat = test::projectedParameterization(flat, Vector3d::UnitX(), Vector3d::UnitY());
  const AdditiveDraft same = additiveDraft(*source, *onFlat, {});
  const TriMesh& canvas = source->canvas->surface;
  for (auto v : canvas.vertices())
    EXPECT_LT((pointOf(same.draft, v.idx()) - pointOf(canvas, v.idx())).norm(), 0.02 * 0.3)
        << v.idx();
  EXPECT_NEAR(same.largestDetail, 0.3, 0.02);
  // The base is the plane under the bump.
  for (auto v : same.base.vertices())
    EXPECT_NEAR(same.base.point(v)[2], 0.0, 2e-3) << v.idx();

  // A tilted target at half the scale: the bump at half its height along the tilted normal.
  const Eigen::Isometry3d tilt(Eigen::AngleAxisd(0.4, Vector3d::UnitX()));
  auto tilted = std::const_pointer_cast<Parameterization>(
      test::projectedParameterization(test::heightGrid(
                                          40, [](double, double) { return 0.0; }, tilt),
                                      tilt * Vector3d::UnitX(), tilt * Vector3d::UnitY()));
  tilted->scale = 0.5;
  for (auto& uv : tilted->uv)
    uv *= 2.0;  // domain distance = target distance / scale
  tilted->origin.normal = tilt * Vector3d::UnitZ();
  tilted->origin.uAxis = tilt * Vector3d::UnitX();
  const AdditiveDraft half = additiveDraft(*source, *tilted, {});
  for (auto v : canvas.vertices()) {
    const Vector3d p = pointOf(canvas, v.idx());
    const Vector3d expected = tilt * Vector3d(0.5 * p.x(), 0.5 * p.y(), 0.5 * bump(p.x(), p.y()));
    EXPECT_LT((pointOf(half.draft, v.idx()) - expected).norm(), 0.02 * 0.3) << v.idx();
  }
  // Gain 0 lays the canvas onto the target's surface.
  const AdditiveDraft none = additiveDraft(*source, *onFlat, {.gain = 0.0});
  for (auto v : none.draft.vertices())
    EXPECT_NEAR(none.draft.point(v)[2], 0.0, 1e-12);
}

// The node on a real mesh, the terrain added onto itself: the draft keeps the source canvas'
// connectivity and reports the detail's size; a canvas without a boundary is refused.
TEST(AdditiveDraftNode, DraftsARealTerrainAndRefusesAClosedCanvas) {
  const auto mountain = test::terrainParameterization();
  auto source = std::make_shared<Parameterization>(*mountain);
  auto canvas = std::make_shared<Canvas>(*mountain->canvas);
  canvas->source = std::make_shared<const Mesh>(canvas->surface);
  for (auto v : canvas->surface.vertices())
    canvas->sourceVertex.push_back(v.idx());
  source->canvas = canvas;
  const test::NodeRun run =
      test::runNode("geobrush.additive_draft", {{"source", source}, {"target", source}});
  const auto draft = run.get<Mesh>("draft");
  const auto report = run.get<Metrics>("report");
  ASSERT_TRUE(draft && report);
  EXPECT_EQ(draft->surface.n_vertices(), canvas->surface.n_vertices());
  EXPECT_GT(report->values.at("largest_detail"), 0.0);

  auto closed = std::make_shared<Parameterization>(*source);
  auto sphere = std::make_shared<Canvas>(*canvas);
  sphere->surface = test::icosphere(2);
  closed->canvas = sphere;
  closed->uv.assign(sphere->surface.n_vertices(), Eigen::Vector2d::Zero());
  try {
    test::runNode("geobrush.additive_draft", {{"source", closed}, {"target", source}});
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'source'");
  }
}

}  // namespace
}  // namespace geobrush
