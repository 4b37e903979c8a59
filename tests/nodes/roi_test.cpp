// geobrush.roi: the painted region Q on its grid and the canvas vertices it selects.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "roi.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

std::shared_ptr<Parameterization> flatSquare(int n) {
  return test::heightFieldParameterization(n, [](double, double) { return 0.0; });
}

// The same square canvas with its uv moved by `shift`: a target that covers part of the source.
std::shared_ptr<Parameterization> shifted(const Parameterization& param, Eigen::Vector2d shift) {
  auto moved = std::make_shared<Parameterization>(param);
  for (auto& u : moved->uv)
    u += shift;
  return moved;
}

Strokes strokes(std::vector<Dab> dabs) {
  Strokes s;
  s.dabs = std::move(dabs);
  return s;
}

std::vector<int> verticesWithin(const Parameterization& param, const Strokes& s,
                                const std::function<bool(const Eigen::Vector2d&)>& covered) {
  std::vector<int> result;
  for (std::size_t v = 0; v < param.uv.size(); ++v)
    if (s.contains(param.uv[v]) && covered(param.uv[v])) result.push_back(int(v));
  return result;
}

bool inSquare(const Eigen::Vector2d& u, const Eigen::Vector2d& shift = Eigen::Vector2d::Zero()) {
  return ((u - shift).array().abs() <= 1 + 1e-12).all();
}

}  // namespace

TEST(RoiGrid, CoversTheSourceDomainWithABorder) {
  auto param = flatSquare(10);
  const DomainGrid grid = roiGrid(*param, 64);
  EXPECT_EQ(grid.width, 64);
  EXPECT_EQ(grid.height, 64);
  EXPECT_DOUBLE_EQ(grid.spacing, 2.0 / (64 - 1 - 2 * kRoiBorder));
  EXPECT_TRUE(grid.origin.isApprox(Eigen::Vector2d::Constant(-1 - kRoiBorder * grid.spacing)));
  EXPECT_GE(grid.position(grid.width - 1, grid.height - 1).x(),
            1 + (kRoiBorder - 1e-9) * grid.spacing);
  EXPECT_THROW(roiGrid(*param, 8), RoiError);
}

TEST(RoiGrid, CoverageIsTheCanvasDomain) {
  auto param = flatSquare(10);
  const DomainGrid grid = roiGrid(*param, 40);
  const auto covered = domainCoverage(*param, grid);
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i)
      EXPECT_EQ(covered[grid.index(i, j)] != 0, inSquare(grid.position(i, j))) << i << " " << j;
}

TEST(Roi, ADiscSelectsTheVerticesAndNodesInside) {
  auto param = flatSquare(20);
  const Strokes s = strokes({{{0.1, -0.2}, 0.45, false}});
  const RoiResult result = paintRegion(s, *param, *param, RoiOptions{64});
  const auto all = [](const Eigen::Vector2d&) { return true; };
  EXPECT_EQ(result.region.sourceVertices, verticesWithin(*param, s, all));
  EXPECT_EQ(result.region.targetVertices, verticesWithin(*param, s, all));
  EXPECT_FALSE(result.region.sourceVertices.empty());
  const DomainGrid& grid = result.region.grid;
  std::size_t nodes = 0;
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i) {
      const bool in = (grid.position(i, j) - Eigen::Vector2d(0.1, -0.2)).norm() <= 0.45;
      EXPECT_EQ(result.region.inside[grid.index(i, j)] != 0, in);
      nodes += in;
    }
  // About pi r^2 / h^2 nodes.
  EXPECT_NEAR(double(nodes), M_PI * 0.45 * 0.45 / (grid.spacing * grid.spacing), 0.1 * nodes);
  EXPECT_TRUE(result.dabsOutside.empty());
}

TEST(Roi, KeepsToWhatBothCanvasesCover) {
  auto source = flatSquare(20);
  const Eigen::Vector2d shift(1.2, 0);
  auto target = shifted(*source, shift);  // covers u in [0.2, 2.2]
  const Strokes s = strokes({{{0.5, 0}, 0.6, false}});
  const RoiResult result = paintRegion(s, *source, *target, RoiOptions{64});
  EXPECT_EQ(result.region.sourceVertices, verticesWithin(*source, s, [&](const Eigen::Vector2d& u) {
              return inSquare(u, shift);
            }));
  EXPECT_EQ(result.region.targetVertices,
            verticesWithin(*target, s, [&](const Eigen::Vector2d& u) { return inSquare(u); }));
  const DomainGrid& grid = result.region.grid;
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i)
      if (result.region.inside[grid.index(i, j)]) {
        EXPECT_GE(grid.position(i, j).x(), 0.2 - 1e-12);
        EXPECT_LE(grid.position(i, j).x(), 1 + 1e-12);
      }
}

TEST(Roi, AnEraserDabRemovesWhatItCovers) {
  auto param = flatSquare(20);
  const RoiResult painted =
      paintRegion(strokes({{{0, 0}, 0.5, false}}), *param, *param, RoiOptions{64});
  const RoiResult erased = paintRegion(strokes({{{0, 0}, 0.5, false}, {{0.25, 0}, 0.2, true}}),
                                       *param, *param, RoiOptions{64});
  EXPECT_LT(erased.region.sourceVertices.size(), painted.region.sourceVertices.size());
  for (int v : erased.region.sourceVertices)
    EXPECT_GT((param->uv[std::size_t(v)] - Eigen::Vector2d(0.25, 0)).norm(), 0.2);
}

TEST(Roi, ALongStrokeOfAddedAndErasedDabsSelectsWhatItsDabsSayInOrder) {
  // Dabs of many sizes along a spiral, every third one erasing, some reaching past the canvas:
  // the region is what Strokes::contains says, dab by dab in stroke order.
  auto param = flatSquare(40);
  std::vector<Dab> dabs;
  for (int d = 0; d < 120; ++d) {
    const double t = 0.15 * d, r = 0.1 + 0.009 * d;
    dabs.push_back({{r * std::cos(t), r * std::sin(t)}, 0.02 + 0.05 * (d % 5), d % 3 == 2});
  }
  dabs.push_back({{-0.9, 0.9}, 1.5, false});
  dabs.push_back({{0.3, 0.3}, 0.2, true});
  const Strokes s = strokes(dabs);
  const RoiResult result = paintRegion(s, *param, *param, RoiOptions{96});
  const auto all = [](const Eigen::Vector2d&) { return true; };
  EXPECT_EQ(result.region.sourceVertices, verticesWithin(*param, s, all));
  EXPECT_EQ(result.region.targetVertices, verticesWithin(*param, s, all));
  const DomainGrid& grid = result.region.grid;
  std::size_t mismatches = 0;
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i) {
      const Eigen::Vector2d u = grid.position(i, j);
      mismatches += (result.region.inside[grid.index(i, j)] != 0) != (inSquare(u) && s.contains(u));
    }
  EXPECT_EQ(mismatches, 0u);

  // The draft support, from its definition over the whole grid: R_in, and the corners of the
  // faces under every node the membrane samples (within taxicab distance 2 of Q, and the four
  // nodes around each vertex of R_in).
  std::vector<char> sampled(grid.nodeCount(), 0), support(param->uv.size(), 0);
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i)
      if (result.region.inside[grid.index(i, j)])
        for (int dj = -2; dj <= 2; ++dj)
          for (int di = std::abs(dj) - 2; di <= 2 - std::abs(dj); ++di)
            sampled[grid.index(i + di, j + dj)] = 1;
  for (int v : result.region.sourceVertices) {
    support[std::size_t(v)] = 1;
    const Eigen::Vector2d g = (param->uv[std::size_t(v)] - grid.origin) / grid.spacing;
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di)
        sampled[grid.index(int(std::floor(g.x())) + di, int(std::floor(g.y())) + dj)] = 1;
  }
  const DomainLocator locator(*param);
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i)
      if (sampled[grid.index(i, j)]) {
        const int face = locator.locate(grid.position(i, j)).face;
        for (auto v : param->canvas->surface.fv_range(TriMesh::FaceHandle(face)))
          support[std::size_t(v.idx())] = 1;
      }
  std::vector<int> expected;
  for (std::size_t v = 0; v < support.size(); ++v)
    if (support[v]) expected.push_back(int(v));
  EXPECT_EQ(result.region.draftSupport, expected);
}

// Dab after dab on one coverage, as the node paints: what the memo keeps from earlier dabs
// (located faces and covered vertices) gives each region exactly as a fresh coverage does, with
// dabs added, erased, and reaching past the target canvas.
TEST(Roi, ACoverageKeptFromDabToDabGivesWhatAFreshOneGives) {
  auto source = flatSquare(30);
  auto target = shifted(*source, {0.7, 0.1});
  RoiCoverage kept = roiCoverage(*source, *target, RoiOptions{80});
  std::vector<Dab> dabs;
  for (int d = 0; d < 12; ++d) {
    const double t = 0.5 * d;
    dabs.push_back({{0.6 * std::cos(t), 0.6 * std::sin(t)}, 0.15 + 0.05 * (d % 3), d % 4 == 3});
    const Strokes s = strokes(dabs);
    const RoiResult memoized = paintRegion(s, *source, *target, kept);
    const RoiResult fresh = paintRegion(s, *source, *target, RoiOptions{80});
    EXPECT_EQ(memoized.region.inside, fresh.region.inside) << "dab " << d;
    EXPECT_EQ(memoized.region.sourceVertices, fresh.region.sourceVertices) << "dab " << d;
    EXPECT_EQ(memoized.region.targetVertices, fresh.region.targetVertices) << "dab " << d;
    EXPECT_EQ(memoized.region.draftSupport, fresh.region.draftSupport) << "dab " << d;
    EXPECT_EQ(memoized.dabsOutside, fresh.dabsOutside) << "dab " << d;
  }
  EXPECT_GT(std::count(kept.target->sourceCovered.begin(), kept.target->sourceCovered.end(), 0), 0)
      << "some painted source vertices lie outside the target canvas";
}

// Dragging the target canvas: a coverage moved to each new target keeps the source's part and
// gives what a fresh coverage gives, with the target partly off the source and then across it,
// and the node gives the same through a drag.
TEST(Roi, ACoverageMovedWithTheTargetGivesWhatAFreshOneGives) {
  auto source = flatSquare(30);
  RoiCoverage moved = roiCoverage(*source, *shifted(*source, {0.9, 0.0}), RoiOptions{80});
  const auto sourceLocator = moved.sourceLocator;
  const auto sourceSide = moved.source;
  const Strokes s = strokes({{{0.3, 0.1}, 0.5, false}, {{-0.2, -0.3}, 0.3, false}});
  const NodeType* type = test::registry().find("geobrush.roi");
  ASSERT_TRUE(type);
  auto node = type->create();
  auto strokesValue = std::make_shared<const Strokes>(s);
  ParamMap params;
  params["resolution"] = 80;
  for (int step = 0; step < 6; ++step) {
    SCOPED_TRACE(step);
    const auto target = shifted(*source, {0.8 - 0.25 * step, 0.05 * step});
    moved = moveTarget(moved, *source, *target);
    const RoiResult viaMoved = paintRegion(s, *source, *target, moved);
    const RoiResult fresh = paintRegion(s, *source, *target, RoiOptions{80});
    EXPECT_EQ(viaMoved.region.inside, fresh.region.inside);
    EXPECT_EQ(viaMoved.region.sourceVertices, fresh.region.sourceVertices);
    EXPECT_EQ(viaMoved.region.targetVertices, fresh.region.targetVertices);
    EXPECT_EQ(viaMoved.region.draftSupport, fresh.region.draftSupport);
    EXPECT_EQ(viaMoved.dabsOutside, fresh.dabsOutside);
    EXPECT_EQ(moved.sourceLocator, sourceLocator);
    EXPECT_EQ(moved.source, sourceSide);

    test::DirectContext ctx(
        *type, {{"strokes", strokesValue}, {"source", source}, {"target", target}}, params);
    node->compute(ctx);
    const auto region = std::dynamic_pointer_cast<const Region2D>(ctx.outputs["region"]);
    ASSERT_TRUE(region);
    EXPECT_EQ(region->inside, fresh.region.inside);
    EXPECT_EQ(region->sourceVertices, fresh.region.sourceVertices);
    EXPECT_EQ(region->targetVertices, fresh.region.targetVertices);
  }
}

// The node keeps nothing: what it derives (the source side, the target side, a locator on each
// canvas) is the framework's, and a new target canvas rebuilds only the target's part.
TEST(RoiNode, DerivesTheSourceSideOnceAcrossTargetsAndKeepsNoState) {
  auto source = flatSquare(30);
  const Strokes s = strokes({{{0.3, 0.1}, 0.5, false}});
  const NodeType* type = test::registry().find("geobrush.roi");
  ASSERT_TRUE(type);
  auto store = std::make_shared<DerivedStore>();
  ParamMap params;
  params["resolution"] = 80;
  auto strokesValue = std::make_shared<const Strokes>(s);
  std::uint64_t builds = 0;
  for (int step = 0; step < 3; ++step) {
    SCOPED_TRACE(step);
    const auto target = shifted(*source, {0.5 - 0.2 * step, 0.1});
    auto node = type->create();  // a fresh instance each time: nothing is kept in the node
    test::DirectContext ctx(
        *type, {{"strokes", strokesValue}, {"source", source}, {"target", target}}, params, store);
    node->compute(ctx);
    const auto region = std::dynamic_pointer_cast<const Region2D>(ctx.outputs["region"]);
    ASSERT_TRUE(region);
    const RoiResult fresh = paintRegion(s, *source, *target, RoiOptions{80});
    EXPECT_EQ(region->contentHash(), fresh.region.contentHash());
    // The first step builds both sides and both locators; later ones the target's two.
    EXPECT_EQ(store->builds() - builds, step == 0 ? 4u : 2u);
    builds = store->builds();
  }
}

TEST(Roi, DabsOutsideTheCanvasesAreReportedAndChangeNothing) {
  auto param = flatSquare(20);
  const RoiResult result =
      paintRegion(strokes({{{5, 5}, 0.5, false}, {{0, 0}, 0.3, false}, {{-3, 0}, 0.2, false}}),
                  *param, *param, RoiOptions{64});
  EXPECT_EQ(result.dabsOutside, (std::vector<int>{0, 2}));
  const RoiResult inside =
      paintRegion(strokes({{{0, 0}, 0.3, false}}), *param, *param, RoiOptions{64});
  EXPECT_EQ(result.region.contentHash(), inside.region.contentHash());
}

TEST(Roi, NoStrokesGiveAnEmptyRegion) {
  auto param = flatSquare(8);
  const RoiResult result = paintRegion(Strokes(), *param, *param, RoiOptions{32});
  EXPECT_TRUE(result.region.empty());
  EXPECT_TRUE(result.region.targetVertices.empty());
  EXPECT_EQ(std::count(result.region.inside.begin(), result.region.inside.end(), 1), 0);
}

TEST(Roi, SelectsVerticesOfARealTerrain) {
  auto param = test::terrainParameterization();
  Eigen::Vector2d lo = param->uv.front(), hi = lo;
  for (const auto& u : param->uv) {
    lo = lo.cwiseMin(u);
    hi = hi.cwiseMax(u);
  }
  const Eigen::Vector2d centre = (lo + hi) / 2;
  const double radius = 0.2 * (hi - lo).minCoeff();
  const Strokes s =
      strokes({{centre, radius, false}, {centre + Eigen::Vector2d(radius, 0), radius / 2, false}});
  const RoiResult result = paintRegion(s, *param, *param);
  const auto all = [](const Eigen::Vector2d&) { return true; };
  EXPECT_EQ(result.region.sourceVertices, verticesWithin(*param, s, all));
  EXPECT_GT(result.region.sourceVertices.size(), 100u);
  EXPECT_EQ(result.region.grid.width, 256);
}

TEST(RoiNode, WarnsAboutDabsOutsideAndAnEmptyRegion) {
  const NodeType* type = test::registry().find("geobrush.roi");
  ASSERT_TRUE(type);
  auto param = flatSquare(8);
  auto outside = std::make_shared<Strokes>(strokes({{{9, 9}, 0.5, false}}));
  ParamMap params;
  params["resolution"] = 32;
  test::DirectContext ctx(*type, {{"strokes", outside}, {"source", param}, {"target", param}},
                          params);
  auto node = type->create();
  node->compute(ctx);
  ASSERT_EQ(ctx.warnings.size(), 2u);
  EXPECT_TRUE(test::contains(ctx.warnings[0], "1 dabs (1) paint no point"));
  EXPECT_TRUE(test::contains(ctx.warnings[1], "target stays unchanged"));
  auto region = std::dynamic_pointer_cast<const Region2D>(ctx.outputs["region"]);
  ASSERT_TRUE(region);
  EXPECT_TRUE(region->empty());
}

// A target canvas around a hole of its mesh (as the dem node keeps it for filling): the hole's
// inside counts as covered, so the region and R_in reach across it.
TEST(Roi, AHoleOfTheTargetCanvasCountsAsCovered) {
  auto source = flatSquare(20);
  auto target = std::make_shared<Parameterization>(*flatSquare(20));
  auto canvas = std::make_shared<Canvas>(*target->canvas);
  TriMesh& mesh = canvas->surface;
  mesh.request_face_status();
  mesh.request_edge_status();
  mesh.request_vertex_status();
  for (auto f : mesh.faces()) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (auto v : mesh.fv_range(f))
      centre += Eigen::Vector2d(mesh.point(v)[0], mesh.point(v)[1]) / 3;
    if (centre.cwiseAbs().maxCoeff() < 0.3) mesh.delete_face(f, true);
  }
  mesh.garbage_collection();
  target->uv.clear();
  for (auto v : mesh.vertices()) {
    target->uv.emplace_back(mesh.point(v)[0], mesh.point(v)[1]);
    if (std::max(std::abs(mesh.point(v)[0]), std::abs(mesh.point(v)[1])) > 1 - 1e-12)
      canvas->boundary.push_back(v.idx());
  }
  target->normal.assign(target->uv.size(), Eigen::Vector3d::UnitZ());
  canvas->sourceVertex.resize(mesh.n_vertices());
  target->canvas = canvas;
  ASSERT_EQ(canvasHoles(*target).size(), 1u);

  const RoiResult result =
      paintRegion(strokes({{{0, 0}, 0.5, false}}), *source, *target, RoiOptions{64});
  const auto all = [](const Eigen::Vector2d&) { return true; };
  EXPECT_EQ(result.region.sourceVertices,
            verticesWithin(*source, strokes({{{0, 0}, 0.5, false}}), all));
  const DomainGrid& grid = result.region.grid;
  const std::size_t centre = grid.index(int(std::lround(-grid.origin.x() / grid.spacing)),
                                        int(std::lround(-grid.origin.y() / grid.spacing)));
  EXPECT_EQ(result.region.inside[centre], 1);
}
