// geobrush.metrics: the seam, detail and self-intersection measures of a paste.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/stitch.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "metrics.hpp"
#include "roi.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

double bumps(double x, double y) {
  return 0.15 * std::sin(3 * x) * std::cos(2 * y);
}

Strokes disc(Eigen::Vector2d centre, double radius) {
  Strokes s;
  s.dabs.push_back({centre, radius, false});
  return s;
}

// The bumpy height field pasted into itself at another resolution: an exact paste.
struct BumpPaste {
  std::shared_ptr<Parameterization> source = test::heightFieldParameterization(40, bumps);
  std::shared_ptr<Parameterization> target = test::heightFieldParameterization(29, bumps);
  StitchResult stitched;
  explicit BumpPaste(const TriMesh* draft = nullptr) {
    const RoiResult roi = paintRegion(disc({0.05, 0}, 0.6), *source, *target, RoiOptions{64});
    stitched = stitchPaste(roi.region, *source, draft ? *draft : source->canvas->surface, nullptr,
                           *target);
  }
};

// The metrics node's inputs for a paste: its result, map, target and source.
std::map<std::string, ValuePtr, std::less<>> pasteInputs(const BumpPaste& paste) {
  return {{"mesh", std::make_shared<const Mesh>(paste.stitched.mesh)},
          {"map", std::make_shared<const PasteMap>(paste.stitched.map)},
          {"target", std::make_shared<const Mesh>(paste.target->canvas->surface)},
          {"source", paste.source}};
}

}  // namespace

TEST(TriangleIntersection, AnalyticCases) {
  const Triangle3 flat{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  // Through the middle, apart, touching at a corner, coplanar overlapping, coplanar apart.
  EXPECT_TRUE(trianglesIntersect(flat, {{{0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}}, 1e-12));
  EXPECT_FALSE(trianglesIntersect(flat, {{{0.2, 0.2, 0.1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}}, 1e-12));
  EXPECT_TRUE(trianglesIntersect(flat, {{{1, 0, 0}, {2, 0, 1}, {2, 1, 0}}}, 1e-12));
  EXPECT_FALSE(trianglesIntersect(flat, {{{1.001, 0, 0}, {2, 0, 1}, {2, 1, 0}}}, 1e-12));
  EXPECT_TRUE(trianglesIntersect(flat, {{{0.3, 0.3, 0}, {1, 0.3, 0}, {0.3, 1, 0}}}, 1e-12));
  EXPECT_FALSE(trianglesIntersect(flat, {{{0.6, 0.6, 0}, {1, 0.6, 0}, {0.6, 1, 0}}}, 1e-12));
  // A degenerate triangle never counts.
  EXPECT_FALSE(trianglesIntersect(flat, {{{0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.2, 0.2, 0}}}, 1e-12));
}

TEST(Metrics, NormalJumpsAreTheDihedralAnglesOfACube) {
  const TriMesh cube = test::boxCage({-1, -1, -1}, {1, 1, 1}, 2);
  std::vector<int> edges(cube.n_edges());
  std::iota(edges.begin(), edges.end(), 0);
  std::size_t creases = 0;
  for (double jump : normalJumps(cube, edges)) {
    const bool crease = std::abs(jump - M_PI / 2) < 1e-12;
    EXPECT_TRUE(crease || jump < 1e-12) << jump;
    creases += crease;
  }
  EXPECT_EQ(creases, 12u * 2);  // 12 cube edges, each cut in two
}

TEST(Metrics, SelfIntersectionsCountCrossingFacePairsOnce) {
  TriMesh mesh;
  auto add = [&](const Triangle3& t) {
    std::vector<TriMesh::VertexHandle> v;
    for (const auto& p : t)
      v.push_back(mesh.add_vertex({p.x(), p.y(), p.z()}));
    mesh.add_face(v);
  };
  add({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  add({{{0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}});
  add({{{5, 5, 5}, {6, 5, 5}, {5, 6, 5}}});
  EXPECT_EQ(selfIntersections(mesh, {0}, 1e-12), 1u);
  EXPECT_EQ(selfIntersections(mesh, {0, 1}, 1e-12), 1u);
  EXPECT_EQ(selfIntersections(mesh, {2}, 1e-12), 0u);
}

TEST(Metrics, AnExactPasteHasASmoothSeamAndItsSourceDetail) {
  const BumpPaste paste;
  const PasteMetrics m =
      measurePaste(paste.stitched.mesh, &paste.stitched.map, &paste.target->canvas->surface,
                   &paste.source->canvas->surface);
  auto& v = m.values;
  EXPECT_EQ(v.at("manifold"), 1);
  EXPECT_EQ(v.at("components"), 1);
  EXPECT_EQ(v.at("boundary_loops"), 1);
  EXPECT_EQ(v.at("target_boundary_loops"), 1);
  EXPECT_EQ(v.at("seam_unshared_vertices"), 0);
  EXPECT_GT(v.at("seam_edges"), 50);
  // Both sides lie on the same smooth surface: the seam bends like the target does.
  EXPECT_LT(v.at("seam_normal_jump_p95_deg"), 3 * v.at("target_dihedral_p95_deg"));
  EXPECT_NEAR(v.at("scale_ratio"), 1, 1e-12);
  EXPECT_GT(v.at("detail_vertices"), 100);
  EXPECT_NEAR(v.at("detail_difference_percent"), 0, 1e-9);
  EXPECT_EQ(v.at("new_self_intersections"), 0);
}

TEST(Metrics, ALiftedPasteShowsAtTheSeamAndAScaledOneInTheScale) {
  const BumpPaste exact;
  TriMesh lifted = exact.source->canvas->surface;
  for (auto v : lifted.vertices())
    lifted.point(v)[2] += 0.2;
  const BumpPaste step(&lifted);
  const auto stepMetrics =
      measurePaste(step.stitched.mesh, &step.stitched.map, nullptr, &step.source->canvas->surface);
  const auto exactMetrics = measurePaste(exact.stitched.mesh, &exact.stitched.map, nullptr,
                                         &exact.source->canvas->surface);
  EXPECT_GT(stepMetrics.values.at("seam_normal_jump_mean_deg"),
            5 * exactMetrics.values.at("seam_normal_jump_mean_deg"));
  EXPECT_NEAR(stepMetrics.values.at("detail_difference_percent"), 0, 1e-9);

  TriMesh doubled = exact.source->canvas->surface;
  for (auto v : doubled.vertices())
    doubled.point(v) *= 2;
  const BumpPaste scaled(&doubled);
  const auto scaledMetrics = measurePaste(scaled.stitched.mesh, &scaled.stitched.map, nullptr,
                                          &scaled.source->canvas->surface);
  EXPECT_NEAR(scaledMetrics.values.at("scale_ratio"), 2, 1e-9);
  EXPECT_NEAR(scaledMetrics.values.at("detail_difference_percent"), 0, 1e-6);
  EXPECT_TRUE(test::contains(scaledMetrics.notes.at(1), "times the source's size"));
}

TEST(Metrics, AMeshWithoutASeamGetsItsC0ChecksAndANote) {
  const TriMesh bunny = readMesh(test::meshPath("bunny_small.obj")).mesh->surface;
  const PasteMetrics m = measurePaste(bunny, nullptr, nullptr, nullptr);
  EXPECT_EQ(m.values.at("manifold"), 1);
  EXPECT_EQ(m.values.at("components"), 1);
  EXPECT_EQ(m.values.at("boundary_loops"), 0);
  EXPECT_EQ(m.values.count("seam_edges"), 0u);
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_TRUE(test::contains(m.notes[0], "no seam"));
  // The shared meshes were checked free of self-intersections.
  std::vector<int> all(bunny.n_faces());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(selfIntersections(bunny, all, 1e-9 * 15.76), 0u);
}

TEST(Metrics, ANonManifoldVertexIsReported) {
  // Two triangles sharing one corner only: a bow tie.
  TriMesh bowTie;
  const auto o = bowTie.add_vertex({0, 0, 0});
  bowTie.add_face(o, bowTie.add_vertex({1, 0, 0}), bowTie.add_vertex({1, 1, 0}));
  bowTie.add_face(o, bowTie.add_vertex({-1, 0, 0}), bowTie.add_vertex({-1, -1, 0}));
  const PasteMetrics m = measurePaste(bowTie, nullptr, nullptr, nullptr);
  EXPECT_EQ(m.values.at("manifold"), 0);
  EXPECT_EQ(m.values.at("non_manifold_vertices"), 1);
}

TEST(MetricsNode, RefusesAMapOfAnotherMesh) {
  const NodeType* type = test::registry().find("geobrush.metrics");
  ASSERT_TRUE(type);
  const BumpPaste paste;
  auto map = std::make_shared<PasteMap>(paste.stitched.map);
  map->sourceVertex.pop_back();
  test::DirectContext ctx(
      *type, {{"mesh", std::make_shared<const Mesh>(paste.stitched.mesh)}, {"map", map}});
  try {
    type->create()->compute(ctx);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'map'");
    EXPECT_TRUE(test::contains(e.what(), "does not describe"));
  }
}

TEST(MetricsNode, MeasuresAPasteFromItsInputs) {
  const NodeType* type = test::registry().find("geobrush.metrics");
  ASSERT_TRUE(type);
  const BumpPaste paste;
  test::DirectContext ctx(*type, pasteInputs(paste));
  type->create()->compute(ctx);
  const auto metrics = std::dynamic_pointer_cast<const Metrics>(ctx.outputs.at("metrics"));
  ASSERT_TRUE(metrics);
  EXPECT_NEAR(metrics->values.at("detail_difference_percent"), 0, 1e-9);
  EXPECT_TRUE(metrics->notes.empty());
}

// require_valid: a clean paste passes; invalidPaste names each problem of a measured one (a real
// paste that fails is in tests/cli/clone_test.cpp).
TEST(MetricsNode, RequireValidPassesACleanPasteAndNamesEachProblem) {
  const NodeType* type = test::registry().find("geobrush.metrics");
  ASSERT_TRUE(type);
  const BumpPaste paste;
  test::DirectContext ctx(*type, pasteInputs(paste), {{"require_valid", true}});
  EXPECT_NO_THROW(type->create()->compute(ctx));

  PasteMetrics measured = measurePaste(paste.stitched.mesh, &paste.stitched.map,
                                       &paste.target->canvas->surface, nullptr);
  EXPECT_EQ(invalidPaste(measured), std::nullopt);
  measured.values["new_self_intersections"] = 7;
  EXPECT_EQ(invalidPaste(measured).value_or(""), "the paste has 7 new self-intersections");
  measured.values["non_manifold_vertices"] = 2;
  measured.values["boundary_loops"] = measured.values.at("target_boundary_loops") + 1;
  EXPECT_EQ(invalidPaste(measured).value_or(""),
            "the paste has 2 non-manifold vertices, 1 more boundary loops than the target, 7 new "
            "self-intersections");
}

namespace {

// A flat n x n grid of unit squares at height z, two triangles each, facing +z.
TriMesh flatGrid(int n, double z) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      v.push_back(mesh.add_vertex(TriMesh::Point(x, y, z)));
  const auto at = [&](int x, int y) { return v[std::size_t(y * (n + 1) + x)]; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      mesh.add_face(at(x, y), at(x + 1, y), at(x + 1, y + 1));
      mesh.add_face(at(x, y), at(x + 1, y + 1), at(x, y + 1));
    }
  return mesh;
}

}  // namespace

// New vertices lifted by h above a flat reference: every distance is h, the normals agree.
TEST(Metrics, NewVerticesAreMeasuredAgainstAReferenceSurface) {
  const int n = 8;
  TriMesh result = flatGrid(n, 0);
  PasteMap map;
  map.targetVertex.resize(result.n_vertices());
  map.sourceVertex.assign(result.n_vertices(), -1);
  std::iota(map.targetVertex.begin(), map.targetVertex.end(), 0);
  const double h = 0.25;
  for (int v : {30, 31, 40}) {  // interior vertices, lifted together
    map.targetVertex[std::size_t(v)] = -1;
    result.point(TriMesh::VertexHandle(v))[2] = h;
  }
  const TriMesh reference = flatGrid(2 * n, 0);
  PasteMetrics metrics;
  measureAgainstReference(result, map, reference, metrics);
  const double diagonal = boundingDiagonal(result);
  EXPECT_EQ(metrics.values.at("reference_vertices"), 3);
  EXPECT_NEAR(metrics.values.at("reference_mean_distance"), h / diagonal, 1e-15);
  EXPECT_NEAR(metrics.values.at("reference_max_distance"), h / diagonal, 1e-15);
  EXPECT_GT(metrics.values.at("reference_normal_mean_deg"), 0);  // lifted: the normals tilt
  EXPECT_LT(metrics.values.at("reference_normal_mean_deg"), 45);
  PasteMetrics none;
  std::iota(map.targetVertex.begin(), map.targetVertex.end(), 0);
  measureAgainstReference(flatGrid(n, 0), map, reference, none);
  EXPECT_EQ(none.values.at("reference_vertices"), 0);
  EXPECT_EQ(none.notes.size(), 1u);
}

// A bump of height h as the truth and a flat fill as the result: the fill's vertices lie close to
// the bump's foot, but the bump's top stands h above the fill, which the reference's distances to
// the result show.
TEST(Metrics, AReferenceTheResultLeavesOutIsMeasuredFromTheReference) {
  const int n = 8;
  const TriMesh result = flatGrid(n, 0);
  PasteMap map;
  map.targetVertex.resize(result.n_vertices());
  map.sourceVertex.assign(result.n_vertices(), -1);
  std::iota(map.targetVertex.begin(), map.targetVertex.end(), 0);
  map.targetVertex[40] = -1;  // the fill's vertex under the bump's top
  TriMesh reference = flatGrid(n, 0);
  const double h = 3;
  reference.point(TriMesh::VertexHandle(40))[2] = h;
  PasteMetrics metrics;
  measureAgainstReference(result, map, reference, metrics);
  const double diagonal = boundingDiagonal(result);
  EXPECT_EQ(metrics.values.at("reference_vertices"), 1);
  EXPECT_LT(metrics.values.at("reference_max_distance"), h / diagonal);
  EXPECT_NEAR(metrics.values.at("reference_to_result_max_distance"), h / diagonal, 1e-15);
  EXPECT_NEAR(metrics.values.at("reference_to_result_mean_distance"),
              h / diagonal / double(reference.n_vertices()), 1e-15);
}

// The whole bunny measured against the patch its hole case removed, the removed vertices counted
// as new: they lie on the patch, so the distances vanish.
TEST(MetricsNode, TheRemovedVerticesOfAHoleCaseLieOnItsPatch) {
  const NodeType* type = test::registry().find("geobrush.metrics");
  ASSERT_TRUE(type);
  const auto whole = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto patch = readMesh(test::meshPath("cases/bunny_small_back_removed_patch.obj")).mesh;
  auto map = std::make_shared<PasteMap>();
  map->targetVertex.resize(whole->surface.n_vertices());
  map->sourceVertex.assign(whole->surface.n_vertices(), -1);
  std::iota(map->targetVertex.begin(), map->targetVertex.end(), 0);
  // The case's removed interior vertices (cases/bunny_small_back_hole.json).
  for (int v : {38,  41,  55,  83,  93,  100, 107, 116, 127, 129,
                140, 162, 225, 303, 360, 429, 439, 444, 481, 494})
    map->targetVertex[std::size_t(v)] = -1;
  test::DirectContext ctx(*type, {{"mesh", whole}, {"map", map}, {"reference", patch}});
  type->create()->compute(ctx);
  const auto metrics = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["metrics"]);
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->values.at("reference_vertices"), 20);
  EXPECT_LT(metrics->values.at("reference_max_distance"), 1e-9);
  EXPECT_LT(metrics->values.at("reference_to_result_max_distance"), 1e-9);
  EXPECT_LT(metrics->values.at("reference_normal_mean_deg"), 30);

  test::DirectContext unmapped(*type, {{"mesh", whole}, {"reference", patch}});
  try {
    type->create()->compute(unmapped);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'map'");
  }
}
