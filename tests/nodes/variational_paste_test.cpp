// geobrush.variational_paste: the paper's Eq. 3 solved on the stitched mesh with Ceres.
#include <gtest/gtest.h>

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <cmath>
#include <random>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/stitch.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "metrics.hpp"
#include "roi.hpp"
#include "test_support.hpp"
#include "variational_paste.hpp"
#include "variational_paste_cost.hpp"

using namespace geobrush;

namespace {

Strokes disc(Eigen::Vector2d centre, double radius) {
  Strokes s;
  s.dabs.push_back({centre, radius, false});
  return s;
}

double bumps(double x, double y) {
  return 0.15 * std::sin(3 * x) * std::cos(2 * y);
}

// A relief inside the painted disc around (0.05, 0), flat at its outline.
double relief(double x, double y) {
  const double r2 = (x - 0.05) * (x - 0.05) + y * y;
  return 0.12 * std::exp(-14 * r2) * (1 + 0.5 * std::sin(9 * x) * std::cos(7 * y));
}

// A source pasted into a target through a disc of Q, with the region and stitch base kept.
struct Paste {
  std::shared_ptr<Parameterization> source, target;
  Region2D region;
  Paste(std::shared_ptr<Parameterization> s, std::shared_ptr<Parameterization> t,
        Eigen::Vector2d centre = {0.05, 0}, double radius = 0.6)
      : source(std::move(s)), target(std::move(t)) {
    region = paintRegion(disc(centre, radius), *source, *target, RoiOptions{64}).region;
  }
  VariationalPasteResult solve(const TriMesh& draft, VariationalPasteOptions options = {}) const {
    return variationalPaste(region, *source, draft, *target, options);
  }
  StitchResult stitch(const TriMesh& draft) const {
    return stitchPaste(region, *source, draft, nullptr, *target);
  }
};

TriMesh transformed(const TriMesh& mesh, const Eigen::Affine3d& transform) {
  TriMesh out = mesh;
  for (auto v : out.vertices()) {
    const Eigen::Vector3d p = transform * pointOf(out, v.idx());
    out.set_point(v, toPoint(p));
  }
  return out;
}

// The largest distance between the pasted vertices of two results of the same topology.
double largestPastedDistance(const VariationalPasteResult& a, const VariationalPasteResult& b) {
  double largest = 0;
  for (std::size_t v = 0; v < a.mesh.n_vertices(); ++v)
    if (a.map.sourceVertex[v] >= 0)
      largest = std::max(largest, (pointOf(a.mesh, int(v)) - pointOf(b.mesh, int(v))).norm());
  return largest;
}

PasteMetrics measure(const VariationalPasteResult& r, const Paste& paste) {
  return measurePaste(r.mesh, &r.map, &paste.target->canvas->surface,
                      &paste.source->canvas->surface);
}

// The residual of LaplacianResidual written for automatic differentiation: seven scalar
// coordinates (v and six neighbours) and the angle-axis rotation of δ.
struct LaplacianFunctor {
  std::array<double, 7> a;
  double b;
  Eigen::Vector3d delta;
  int k;
  template <typename T>
  bool operator()(const T* x0, const T* x1, const T* x2, const T* x3, const T* x4, const T* x5,
                  const T* x6, const T* w, T* r) const {
    const T* x[7] = {x0, x1, x2, x3, x4, x5, x6};
    T sum = T(b);
    for (int i = 0; i < 7; ++i)
      sum += a[std::size_t(i)] * x[i][0];
    const T d[3] = {T(delta.x()), T(delta.y()), T(delta.z())};
    T rotated[3];
    ceres::AngleAxisRotatePoint(w, d, rotated);
    r[0] = sum - rotated[k];
    return true;
  }
};

// Evaluates a cost function's residuals and Jacobians at `parameters`.
struct Evaluation {
  std::vector<double> residuals;
  std::vector<std::vector<double>> jacobians;
};
Evaluation evaluate(const ceres::CostFunction& cost, const std::vector<std::vector<double>>& at) {
  Evaluation e;
  e.residuals.resize(std::size_t(cost.num_residuals()));
  std::vector<const double*> parameters;
  std::vector<double*> jacobians;
  for (std::size_t i = 0; i < at.size(); ++i) {
    parameters.push_back(at[i].data());
    e.jacobians.emplace_back(std::size_t(cost.num_residuals()) * at[i].size());
  }
  for (auto& j : e.jacobians)
    jacobians.push_back(j.data());
  EXPECT_TRUE(cost.Evaluate(parameters.data(), e.residuals.data(), jacobians.data()));
  return e;
}

void expectSameEvaluation(const Evaluation& hand, const Evaluation& automatic, double tolerance) {
  ASSERT_EQ(hand.residuals.size(), automatic.residuals.size());
  for (std::size_t i = 0; i < hand.residuals.size(); ++i)
    EXPECT_NEAR(hand.residuals[i], automatic.residuals[i], tolerance);
  ASSERT_EQ(hand.jacobians.size(), automatic.jacobians.size());
  for (std::size_t b = 0; b < hand.jacobians.size(); ++b)
    for (std::size_t i = 0; i < hand.jacobians[b].size(); ++i)
      EXPECT_NEAR(hand.jacobians[b][i], automatic.jacobians[b][i], tolerance)
          << "block " << b << " entry " << i;
}

}  // namespace

TEST(VariationalPasteCost, RotationJacobianMatchesAutomaticDifferentiation) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    // Angles from zero to about pi. Below 1.5e-8 Ceres rotates by the first-order p + w x p, so
    // its derivative is off by O(|w| |δ|) there; between that and 1e-2 its Rodrigues formula
    // loses digits to cancellation in 1 - cos, so it is no reference for the series used below
    // 1e-2 (SeriesMeetsTheClosedForm checks that).
    const double scale = trial == 0 ? 0.0 : trial < 3 ? 1e-9 : trial < 10 ? 0.05 * trial : 1.8;
    LaplacianFunctor f;
    for (double& a : f.a)
      a = uniform(random);
    f.b = uniform(random);
    f.delta = {uniform(random), uniform(random), uniform(random)};
    f.k = trial % 3;
    std::vector<std::vector<double>> at;
    for (int i = 0; i < 7; ++i)
      at.push_back({uniform(random)});
    at.push_back({scale * uniform(random), scale * uniform(random), scale * uniform(random)});
    const LaplacianResidual hand(std::vector<double>(f.a.begin(), f.a.end()), f.b, f.delta, f.k);
    const ceres::AutoDiffCostFunction<LaplacianFunctor, 1, 1, 1, 1, 1, 1, 1, 1, 3> automatic(
        new LaplacianFunctor(f));
    SCOPED_TRACE("trial " + std::to_string(trial));
    const double firstOrder = scale < 1e-8 ? 2 * scale * f.delta.norm() : 0.0;
    expectSameEvaluation(evaluate(hand, at), evaluate(automatic, at), 1e-13 + firstOrder);
  }
}

TEST(VariationalPasteCost, LinearJacobianMatchesAutomaticDifferentiation) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    // Without a rotation the residual is the functor's with w = 0 and δ folded into b.
    LaplacianFunctor f;
    for (double& a : f.a)
      a = uniform(random);
    f.b = uniform(random);
    f.delta = {uniform(random), uniform(random), uniform(random)};
    f.k = trial % 3;
    std::vector<std::vector<double>> at;
    for (int i = 0; i < 7; ++i)
      at.push_back({uniform(random)});
    const LaplacianResidual hand(std::vector<double>(f.a.begin(), f.a.end()), f.b - f.delta[f.k]);
    const ceres::AutoDiffCostFunction<LaplacianFunctor, 1, 1, 1, 1, 1, 1, 1, 1, 3> automatic(
        new LaplacianFunctor(f));
    Evaluation expected = evaluate(automatic, [&] {
      auto withRotation = at;
      withRotation.push_back({0, 0, 0});
      return withRotation;
    }());
    expected.jacobians.pop_back();
    expectSameEvaluation(evaluate(hand, at), expected, 1e-14);
  }
}

// The rotation switches from its series to the closed form at 0.01 radians without a jump.
TEST(VariationalPasteCost, SeriesMeetsTheClosedForm) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.7, 0.2).normalized(), d(1, 2, -0.5);
  const RotatedPoint below = rotateWithJacobian(axis * (1e-2 * (1 - 1e-15)), d);
  const RotatedPoint above = rotateWithJacobian(axis * (1e-2 * (1 + 1e-15)), d);
  EXPECT_LT((below.point - above.point).norm(), 1e-15);
  EXPECT_LT((below.jacobian - above.jacobian).norm(), 1e-15);
}

TEST(VariationalPasteCost, RotatedPointIsCeresRotation) {
  const Eigen::Vector3d w(0.3, -0.7, 0.2), d(1, 2, -0.5);
  Eigen::Vector3d expected;
  ceres::AngleAxisRotatePoint(w.data(), d.data(), expected.data());
  EXPECT_LT((rotateWithJacobian(w, d).point - expected).norm(), 1e-15);
}

// A flat source, lifted and tilted, pasted into a flat target of another resolution: the gap is
// affine in (u, v), which the mean-value Laplacian's biharmonic offset reproduces exactly, skinny
// seam triangles and all, so the paste lands flat in the target's plane. The uniform Laplacian
// has no such precision on the seam strips.
TEST(VariationalPaste, AFlatPasteStaysFlat) {
  const Paste paste(test::heightFieldParameterization(24, [](double, double) { return 0.0; }),
                    test::heightFieldParameterization(17, [](double, double) { return 0.0; }));
  const Eigen::Affine3d lift = Eigen::Translation3d(0.1, 0, 0.2) *
                               Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0).normalized());
  const TriMesh lifted = transformed(paste.source->canvas->surface, lift);
  const VariationalPasteResult result = paste.solve(lifted);
  ASSERT_GT(result.report.unknownVertices, 100u);
  EXPECT_GT(result.report.ringVertices, 20u);
  for (auto v : result.mesh.vertices())
    EXPECT_NEAR(result.mesh.point(v)[2], 0, 1e-9) << v.idx();
  EXPECT_LE(result.report.linearIterations, 2);
  EXPECT_EQ(result.report.rotationIterations, 0);

  VariationalPasteOptions uniform;
  uniform.weights = LaplacianWeights::Uniform;
  const TriMesh uniformMesh = paste.solve(lifted, uniform).mesh;
  double largest = 0;
  for (auto v : uniformMesh.vertices())
    largest = std::max(largest, std::abs(uniformMesh.point(v)[2]));
  EXPECT_GT(largest, 1e-4);
}

// Each solver iteration reports the share of the iteration budget spent, rising in [0, 1).
TEST(VariationalPaste, ReportsProgressPerIteration) {
  const Paste paste(test::heightFieldParameterization(29, bumps),
                    test::heightFieldParameterization(21, bumps));
  std::vector<double> reports;
  VariationalPasteOptions options;
  options.progress = [&](double fraction) { reports.push_back(fraction); };
  const VariationalPasteResult result = paste.solve(paste.source->canvas->surface, options);
  ASSERT_GE(reports.size(), std::size_t(result.report.linearIterations + 1));
  EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
  EXPECT_GE(reports.front(), 0.0);
  EXPECT_LT(reports.back(), 1.0);
  if (result.report.rotationIterations > 0) {
    EXPECT_GE(reports.back(), 0.5);
  }
}

// The draft is the target surface itself, sampled on the same grid: δ is exact, and the solve
// gives back the target's positions.
TEST(VariationalPaste, AnExactDraftReproducesTheTarget) {
  const Paste paste(test::heightFieldParameterization(29, bumps),
                    test::heightFieldParameterization(29, bumps));
  TriMesh draft = paste.source->canvas->surface;
  const VariationalPasteResult result = paste.solve(draft);
  for (auto v : result.mesh.vertices()) {
    const auto& p = result.mesh.point(v);
    EXPECT_NEAR(p[2], bumps(p[0], p[1]), 1e-9) << v.idx();
  }
  // Lifted, it comes back down all the same: the offset is the constant gap.
  const VariationalPasteResult lifted =
      paste.solve(transformed(draft, Eigen::Affine3d(Eigen::Translation3d(0.1, -0.2, 0.3))));
  EXPECT_LT(largestPastedDistance(lifted, result), 1e-9);
}

// At another resolution the draft's samples at the fixed rings are linear interpolations of the
// bumps, and past the draft support the target plus an affine extension of the draft's height
// over the target's linear interpolation: the paste stays on the target surface to about that
// interpolation's error, its detail is the source's, and its seam is as smooth as the target.
TEST(VariationalPaste, ABumpPasteAtAnotherResolutionStaysOnTheSurface) {
  const Paste paste(test::heightFieldParameterization(40, bumps),
                    test::heightFieldParameterization(29, bumps));
  const VariationalPasteResult result = paste.solve(paste.source->canvas->surface);
  double largest = 0;
  for (auto v : result.mesh.vertices()) {
    const auto& p = result.mesh.point(v);
    largest = std::max(largest, std::abs(p[2] - bumps(p[0], p[1])));
  }
  EXPECT_LT(largest, 3e-3);
  const PasteMetrics m = measure(result, paste);
  EXPECT_EQ(m.values.at("manifold"), 1);
  EXPECT_LT(m.values.at("detail_difference_percent"), 3);
  EXPECT_LT(m.values.at("seam_normal_jump_p95_deg"), 3 * m.values.at("target_dihedral_p95_deg"));
  RecordProperty("largest_height_error", std::to_string(largest));
}

// The result has stitch's topology and map: only the pasted vertices move.
TEST(VariationalPaste, KeepsTheStitchTopologyAndMap) {
  const Paste paste(test::heightFieldParameterization(30, bumps),
                    test::heightFieldParameterization(22, bumps));
  const Paste annulus(paste.source, paste.target, {0, 0}, 0.7);
  for (const Paste* p : {&paste, &annulus}) {
    const TriMesh draft =
        transformed(p->source->canvas->surface, Eigen::Affine3d(Eigen::Translation3d(0, 0, 0.25)));
    const StitchResult stitched = p->stitch(draft);
    const VariationalPasteResult result = p->solve(draft);
    EXPECT_EQ(test::faceIndices(result.mesh), test::faceIndices(stitched.mesh));
    EXPECT_EQ(result.map.sourceVertex, stitched.map.sourceVertex);
    EXPECT_EQ(result.map.targetVertex, stitched.map.targetVertex);
    EXPECT_EQ(result.map.seamFaces, stitched.map.seamFaces);
    const test::Topology topology = test::topology(result.mesh);
    EXPECT_EQ(topology.nonManifoldVertices, 0u);
    EXPECT_EQ(topology.boundaryLoops, 1u);
    EXPECT_EQ(topology.components, 1u);
    for (auto v : result.mesh.vertices())
      if (result.map.sourceVertex[std::size_t(v.idx())] < 0) {
        EXPECT_EQ(result.mesh.point(v), stitched.mesh.point(v));
      }
  }
}

// A draft floating above a curved target: pasted as it is, the seam is a step; solved, the paste
// meets the target with its slope.
TEST(VariationalPaste, MeetsACurvedTargetSmoothly) {
  const auto bowl = [](double x, double y) { return 0.6 * (x * x + y * y) + 0.3 * x; };
  const Paste paste(test::heightFieldParameterization(40, bumps),
                    test::heightFieldParameterization(40, bowl), {0, 0}, 0.55);
  const TriMesh draft =
      transformed(paste.source->canvas->surface, Eigen::Affine3d(Eigen::Translation3d(0, 0, 0.25)));
  const StitchResult stitched = paste.stitch(draft);
  const VariationalPasteResult result = paste.solve(draft);
  const auto raw = measurePaste(stitched.mesh, &stitched.map, nullptr, nullptr).values;
  const auto solved = measure(result, paste).values;
  EXPECT_LT(solved.at("seam_normal_jump_p95_deg"), 0.1 * raw.at("seam_normal_jump_p95_deg"));
  EXPECT_LT(solved.at("seam_normal_jump_p95_deg"), 3 * solved.at("target_dihedral_p95_deg"));
  EXPECT_EQ(solved.at("new_self_intersections"), 0);
}

// A draft tilted by 30 degrees against the target (a badly fitted cage): the linear solve keeps
// δ's direction and shears the relief; the rotation-invariant solve turns it back and lands on
// the paste of the untilted draft.
TEST(VariationalPaste, RotationInvariantModeRecoversATiltedDetail) {
  const Paste paste(test::heightFieldParameterization(40, relief),
                    test::heightFieldParameterization(29, [](double, double) { return 0.0; }));
  const TriMesh& source = paste.source->canvas->surface;
  const VariationalPasteResult reference = paste.solve(source);
  const Eigen::Affine3d tilt = Eigen::Translation3d(0.05, 0, 0) *
                               Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitX()) *
                               Eigen::Translation3d(-0.05, 0, 0);
  const TriMesh tilted = transformed(source, tilt);
  const VariationalPasteResult linear = paste.solve(tilted);
  VariationalPasteOptions options;
  options.rotationInvariant = true;
  const VariationalPasteResult invariant = paste.solve(tilted, options);
  EXPECT_GT(invariant.report.rotationIterations, 0);
  EXPECT_EQ(invariant.report.rotations,
            invariant.report.unknownVertices + invariant.report.ringVertices);

  const double linearError = largestPastedDistance(linear, reference);
  const double invariantError = largestPastedDistance(invariant, reference);
  EXPECT_GT(linearError, 0.02);
  EXPECT_LT(invariantError, 0.2 * linearError);
  const double linearDetail = measure(linear, paste).values.at("detail_difference_percent");
  const double invariantDetail = measure(invariant, paste).values.at("detail_difference_percent");
  // The Laplacian magnitudes do not tell the two apart: the linear solve shears the relief whole,
  // which keeps them (L has linear precision); its direction is what goes wrong.
  EXPECT_LT(invariantDetail, 1.5);
  RecordProperty("linear_error", std::to_string(linearError));
  RecordProperty("invariant_error", std::to_string(invariantError));
  RecordProperty("linear_detail_percent", std::to_string(linearDetail));
  RecordProperty("invariant_detail_percent", std::to_string(invariantDetail));
}

TEST(VariationalPaste, AnEmptyRegionLeavesTheTarget) {
  auto param = test::heightFieldParameterization(8, bumps);
  const Region2D region = paintRegion(Strokes(), *param, *param, RoiOptions{32}).region;
  const VariationalPasteResult result =
      variationalPaste(region, *param, param->canvas->surface, *param);
  EXPECT_TRUE(test::bitIdentical(result.mesh, param->canvas->surface));
  EXPECT_EQ(result.report.unknownVertices, 0u);
}

TEST(VariationalPaste, ABadDraftOrAnUnconvergedSolveThrows) {
  const Paste paste(test::heightFieldParameterization(20, relief),
                    test::heightFieldParameterization(20, [](double, double) { return 0.0; }));
  TriMesh wrong;
  EXPECT_THROW(paste.solve(wrong), VariationalPasteError);
  TriMesh broken = paste.source->canvas->surface;
  broken.point(TriMesh::VertexHandle(3))[1] = std::nan("");
  EXPECT_THROW(paste.solve(broken), VariationalPasteError);

  VariationalPasteOptions options;
  options.cancelled = [] { return true; };
  try {
    paste.solve(paste.source->canvas->surface, options);
    FAIL() << "no error";
  } catch (const VariationalPasteSolveError& e) {
    EXPECT_TRUE(e.cancelled());
  }
}

// The mountain's terrain pasted into itself with the draft lifted along its up axis: whatever
// the irregular triangles, the solve brings the paste back onto the terrain.
TEST(VariationalPaste, ClosesAConstantGapOnARealTerrain) {
  auto terrain = test::terrainParameterization();
  Eigen::Vector2d lo = terrain->uv.front(), hi = lo;
  for (const auto& u : terrain->uv) {
    lo = lo.cwiseMin(u);
    hi = hi.cwiseMax(u);
  }
  const Region2D region =
      paintRegion(disc((lo + hi) / 2, 0.2 * (hi - lo).minCoeff()), *terrain, *terrain).region;
  ASSERT_FALSE(region.empty());
  const TriMesh& surface = terrain->canvas->surface;
  const TriMesh draft = transformed(surface, Eigen::Affine3d(Eigen::Translation3d(0, 1.5, 0)));
  const VariationalPasteResult result = variationalPaste(region, *terrain, draft, *terrain);
  EXPECT_GT(result.report.unknownVertices, 500u);
  double largest = 0;
  for (std::size_t v = 0; v < result.mesh.n_vertices(); ++v) {
    const int s = result.map.sourceVertex[v];
    if (s >= 0)
      largest = std::max(largest, (pointOf(result.mesh, int(v)) - pointOf(surface, s)).norm());
  }
  // The terrain spans about 50 units: 1e-6 is the normal equations' round-off at its size.
  EXPECT_LT(largest, 1e-6);
  const PasteMetrics m = measurePaste(result.mesh, &result.map, &surface, &surface);
  EXPECT_EQ(m.values.at("manifold"), 1);
  EXPECT_EQ(m.values.at("new_self_intersections"), 0);
}

// A warp of the region (geobrush.gc_warp with its region connected) moves only the draft
// support, R_in and the source vertices under two grid nodes around Q, and leaves every other
// draft vertex at its source position, far from the target in a real clone. On a target coarser
// than the region's grid the fixed rings reach past that support: the paste reads the draft
// there by its extension, so the vertices outside the support change nothing, and the relief
// lands on the coarse flat target as the whole draft's paste does.
TEST(VariationalPaste, ReadsTheDraftOnlyOnItsSupport) {
  const Paste paste(test::heightFieldParameterization(40, relief),
                    test::heightFieldParameterization(12, [](double, double) { return 0.0; }));
  const TriMesh& whole = paste.source->canvas->surface;
  std::vector<char> support(whole.n_vertices(), 0);
  for (int v : paste.region.draftSupport)
    support[std::size_t(v)] = 1;
  TriMesh partial = whole;
  std::size_t unwarped = 0;
  for (auto v : partial.vertices())
    if (!support[std::size_t(v.idx())]) {
      partial.point(v)[1] += 20;
      partial.point(v)[2] += 50;
      ++unwarped;
    }
  ASSERT_GT(unwarped, 100u);

  const VariationalPasteResult result = paste.solve(partial);
  EXPECT_EQ(largestPastedDistance(result, paste.solve(whole)), 0);
  double lowest = 0, highest = 0;
  for (std::size_t v = 0; v < result.mesh.n_vertices(); ++v)
    if (result.map.sourceVertex[v] >= 0) {
      lowest = std::min(lowest, pointOf(result.mesh, int(v)).z());
      highest = std::max(highest, pointOf(result.mesh, int(v)).z());
    }
  // The relief peaks at 0.18 and falls to 1e-3 at Q's outline.
  EXPECT_GT(lowest, -0.01);
  EXPECT_LT(highest, 0.2);
  const PasteMetrics m = measure(result, paste);
  EXPECT_EQ(m.values.at("new_self_intersections"), 0);
  EXPECT_NEAR(m.values.at("scale_ratio"), 1, 0.05);
  EXPECT_LT(m.values.at("detail_difference_percent"), 2.5);
  RecordProperty("detail_difference_percent",
                 std::to_string(m.values.at("detail_difference_percent")));
}

TEST(VariationalPasteNode, OutputsTheSolvedPasteAndItsReport) {
  const NodeType* type = test::registry().find("geobrush.variational_paste");
  ASSERT_TRUE(type);
  const Paste paste(test::heightFieldParameterization(24, relief),
                    test::heightFieldParameterization(17, [](double, double) { return 0.0; }));
  const TriMesh draft =
      transformed(paste.source->canvas->surface, Eigen::Affine3d(Eigen::Translation3d(0, 0, 0.1)));
  test::DirectContext ctx(*type, {{"region", std::make_shared<const Region2D>(paste.region)},
                                  {"source", paste.source},
                                  {"draft", std::make_shared<const Mesh>(draft)},
                                  {"target", paste.target}});
  type->create()->compute(ctx);
  const auto mesh = std::dynamic_pointer_cast<const Mesh>(ctx.outputs.at("mesh"));
  const auto map = std::dynamic_pointer_cast<const PasteMap>(ctx.outputs.at("map"));
  const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs.at("report"));
  ASSERT_TRUE(mesh && map && report);
  const VariationalPasteResult direct = paste.solve(draft);
  EXPECT_TRUE(test::bitIdentical(mesh->surface, direct.mesh));
  EXPECT_EQ(map->sourceVertex, direct.map.sourceVertex);
  EXPECT_EQ(report->values.at("unknown_vertices"), double(direct.report.unknownVertices));
  EXPECT_EQ(measurePaste(mesh->surface, map.get(), nullptr, nullptr).values.at("manifold"), 1);
}

// A rotation-invariant solve held to one iteration cannot meet the tolerance: the node fails
// naming the param, and outputs nothing.
TEST(VariationalPasteNode, AnUnconvergedSolveIsAnErrorWithoutOutput) {
  const NodeType* type = test::registry().find("geobrush.variational_paste");
  ASSERT_TRUE(type);
  const Paste paste(test::heightFieldParameterization(24, relief),
                    test::heightFieldParameterization(17, [](double, double) { return 0.0; }));
  const Eigen::Affine3d tilt(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitX()));
  test::DirectContext ctx(
      *type,
      {{"region", std::make_shared<const Region2D>(paste.region)},
       {"source", paste.source},
       {"draft", std::make_shared<const Mesh>(transformed(paste.source->canvas->surface, tilt))},
       {"target", paste.target}},
      {{"rotation_invariant", true}, {"max_iterations", std::int64_t(1)}, {"tolerance", 1e-16}});
  try {
    type->create()->compute(ctx);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'max_iterations'");
    EXPECT_TRUE(test::contains(e.what(), "did not converge")) << e.what();
  }
  EXPECT_TRUE(ctx.outputs.empty());
}

// A draft that is not the source canvas' (here another grid's) is refused naming the port.
TEST(VariationalPasteNode, ADraftOfAnotherMeshNamesTheDraft) {
  const NodeType* type = test::registry().find("geobrush.variational_paste");
  ASSERT_TRUE(type);
  const Paste paste(test::heightFieldParameterization(16, relief),
                    test::heightFieldParameterization(16, relief));
  test::DirectContext ctx(*type, {{"region", std::make_shared<const Region2D>(paste.region)},
                                  {"source", paste.source},
                                  {"draft", test::heightGrid(15, relief)},
                                  {"target", paste.target}});
  try {
    type->create()->compute(ctx);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'draft'");
    EXPECT_TRUE(test::contains(e.what(), "source canvas")) << e.what();
  }
  EXPECT_TRUE(ctx.outputs.empty());
}
