// geobrush.cage_fit: Laplacian editing of the source cage onto the target
// parameterization reproduces the cage for identical canvases and follows
// rigid motions and scaling exactly.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "cage_build.hpp"
#include "cage_fit.hpp"
#include "canvas_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

using namespace geobrush;
using Eigen::Vector3d;

namespace {

double bump(double x, double y) {
  return 0.4 * std::exp(-4 * (x * x + y * y));
}

// The same parameterization with its canvas moved by p -> scale R p + t
// (normals turned by R), so that E_t^-1 = that map applied to E_s^-1.
std::shared_ptr<Parameterization> moved(const Parameterization& source, const Eigen::Matrix3d& R,
                                        double scale, const Vector3d& t) {
  auto canvas = std::make_shared<Canvas>(*source.canvas);
  for (auto v : canvas->surface.vertices()) {
    const auto& p = canvas->surface.point(v);
    const Vector3d q = scale * R * Vector3d(p[0], p[1], p[2]) + t;
    canvas->surface.point(v) = toPoint(q);
  }
  auto target = std::make_shared<Parameterization>(source);
  target->canvas = canvas;
  for (auto& n : target->normal)
    n = R * n;
  target->scale = scale;
  return target;
}

double maxDistance(const TriMesh& a, const TriMesh& b, const Eigen::Matrix3d& R, double scale,
                   const Vector3d& t) {
  double worst = 0;
  for (auto v : a.vertices()) {
    const auto& p = a.point(v);
    const auto& q = b.point(v);
    const Vector3d expected = scale * R * Vector3d(p[0], p[1], p[2]) + t;
    worst = std::max(worst, (expected - Vector3d(q[0], q[1], q[2])).norm());
  }
  return worst;
}

}  // namespace

TEST(CageFit, IdenticalCanvasReproducesTheSourceCage) {
  auto param = test::heightFieldParameterization(24, bump);
  const Cage cage = buildCage(*param).cage;
  const CageFitResult fit = fitCage(cage, *param, *param);
  EXPECT_LT(maxDistance(cage.mesh, fit.cage.mesh, Eigen::Matrix3d::Identity(), 1, Vector3d::Zero()),
            1e-9);
  EXPECT_EQ(fit.cage.top, cage.top);
  EXPECT_EQ(fit.cage.domainTriangles, cage.domainTriangles);
}

TEST(CageFit, FollowsSimilarityTransformsExactly) {
  auto param = test::heightFieldParameterization(24, bump);
  const Cage cage = buildCage(*param).cage;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (double scale : {1.0, 2.5}) {
    const Vector3d t(0.3, -4, 2);
    auto target = moved(*param, R, scale, t);
    const CageFitResult fit = fitCage(cage, *param, *target);
    EXPECT_LT(maxDistance(cage.mesh, fit.cage.mesh, R, scale, t), 1e-9 * scale) << scale;
  }
}

TEST(CageFit, ReusedSolverAndColumnsGiveTheSameCage) {
  auto param = test::heightFieldParameterization(16, bump);
  const Cage cage = buildCage(*param).cage;
  auto target = moved(*param, Eigen::Matrix3d::Identity(), 1.3, Vector3d(1, 0, 0));
  const CageFitSolver solver(cage, CageFitOptions{}.constraintWeight);
  const SourceColumns columns(cage, *param);
  const auto fresh = fitCage(cage, *param, *target);
  const auto reused = fitCage(cage, *param, *target, {}, &solver, &columns);
  EXPECT_EQ(fresh.cage.contentHash(), reused.cage.contentHash());
  EXPECT_TRUE(solver.fits(cage, 10.0));
  EXPECT_FALSE(solver.fits(cage, 11.0));
}

TEST(CageFit, RefusesColumnsFoundForAnotherCage) {
  auto param = test::heightFieldParameterization(16, bump);
  const Cage cage = buildCage(*param).cage;
  CageBuildOptions finer;
  finer.resolution = 12;
  const SourceColumns otherColumns(buildCage(*param, finer).cage, *param);
  EXPECT_THROW(fitCage(cage, *param, *param, {}, nullptr, &otherColumns), CageFitError);
}

TEST(CageFit, BentTargetKeepsTheCageAroundIt) {
  auto param = test::heightFieldParameterization(24, bump);
  CageBuildOptions fine;  // a finer cage follows the bend more closely
  fine.resolution = 12;
  const Cage cage = buildCage(*param, fine).cage;
  // Wrap the flat canvas onto a cylinder of radius 2 about the y axis: the
  // target's frames turn with x, so the cage must bend with it.
  auto target = std::make_shared<Parameterization>(*param);
  auto canvas = std::make_shared<Canvas>(*param->canvas);
  for (auto v : canvas->surface.vertices()) {
    auto& p = canvas->surface.point(v);
    const double angle = p[0] / 2, radius = 2 + p[2];
    p = {radius * std::sin(angle), p[1], radius * std::cos(angle) - 2};
    target->normal[v.idx()] = Vector3d(std::sin(angle), 0, std::cos(angle));
  }
  target->canvas = canvas;
  const CageFitResult fit = fitCage(cage, *param, *target);
  EXPECT_TRUE(fit.cage.mesh.n_vertices() == cage.mesh.n_vertices());
  // The cage's far ends tilt with the cylinder: top minus bottom follows the normal.
  double worst = 1;
  for (std::size_t d = 0; d < fit.cage.domain.size(); ++d) {
    const auto& top = fit.cage.mesh.point(TriMesh::VertexHandle(fit.cage.top[d]));
    const auto& bottom = fit.cage.mesh.point(TriMesh::VertexHandle(fit.cage.bottom[d]));
    const Vector3d axis = Vector3d(top[0] - bottom[0], top[1] - bottom[1], top[2] - bottom[2]);
    const double angle = fit.cage.domain[d].x() / 2;
    worst = std::min(worst, axis.normalized().dot(Vector3d(std::sin(angle), 0, std::cos(angle))));
  }
  EXPECT_GT(worst, 0.9);
  EXPECT_EQ(countSelfIntersections(fit.cage.mesh), 0u);
}

TEST(CageFit, RealTerrainMovedRigidly) {
  auto param = test::terrainParameterization();
  CageBuildOptions options;
  options.resolution = 10;
  const Cage cage = buildCage(*param, options).cage;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-1.1, Vector3d::UnitX()).toRotationMatrix();
  auto target = moved(*param, R, 0.5, Vector3d(10, 20, 30));
  const CageFitResult fit = fitCage(cage, *param, *target);
  EXPECT_LT(maxDistance(cage.mesh, fit.cage.mesh, R, 0.5, Vector3d(10, 20, 30)), 1e-8);
}

TEST(CageFit, BadInput) {
  auto param = test::heightFieldParameterization(8, bump);
  const Cage cage = buildCage(*param).cage;
  auto target = std::make_shared<Parameterization>(*param);
  target->scale = 0;
  EXPECT_THROW(fitCage(cage, *param, *target), CageFitError);
  CageFitOptions options;
  options.constraintWeight = -1;
  EXPECT_THROW(fitCage(cage, *param, *param, options), CageFitError);
  Cage broken = cage;
  broken.top.pop_back();
  EXPECT_THROW(fitCage(broken, *param, *param), CageFitError);
}
