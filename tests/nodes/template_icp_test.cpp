#include "template_icp.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/border_loop.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/point_neighbours.hpp"
#include "geobrush/point_pairs.hpp"
#include "geobrush/submesh.hpp"
#include "geobrush/values.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// An uneven surface without symmetries, so that only the true motion lays its border back on it.
double bumpy(double x, double y) {
  return 0.8 * x * x + 0.5 * y * y + 0.4 * x * y + 0.6 * x * x * x - 0.3 * y * y * y;
}

// The template: the height field above, a 10 x 10 grid over [-1, 1]^2. Nearest-vertex ICP
// converges when the motion moves each border point less than about half the spacing of the
// template's vertices around it; on a denser grid the border settles a fraction of an edge away
// (a local minimum of point-to-point ICP).
MeshPtr templateMesh() {
  return test::heightGrid(10, bumpy);
}

const Eigen::Vector2d kHoleCentre(0.1, -0.05);
constexpr double kHoleRadius = 0.45;

// `mesh` without its faces whose centroid lies within `radius` of `centre` in (x, y); vertex
// indices are kept, so the hole's border vertices are also template vertices.
TriMesh withHole(const TriMesh& mesh, const Eigen::Vector2d& centre, double radius) {
  TriMesh holed;
  for (const auto v : mesh.vertices())
    holed.add_vertex(mesh.point(v));
  for (const auto f : mesh.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto v : mesh.fv_range(f)) {
      corners.push_back(v);
      centroid += pointOf(mesh, v) / 3;
    }
    if ((centroid.head<2>() - centre).norm() >= radius) holed.add_face(corners);
  }
  return holed;
}

TriMesh moved(const TriMesh& mesh, const RigidMotion& motion) {
  TriMesh out = mesh;
  for (const auto v : out.vertices())
    out.set_point(v, toPoint(motion(pointOf(out, v))));
  return out;
}

// The loop of `mesh` that does not hold `outer`; `mesh` has two loops.
std::shared_ptr<BorderLoop> innerLoop(const TriMesh& mesh, int outer) {
  auto border = std::make_shared<BorderLoop>();
  border->mesh = std::make_shared<const Mesh>(mesh);
  const auto loops = boundaryLoops(mesh);
  for (const auto& loop : loops)
    if (std::find(loop.begin(), loop.end(), outer) == loop.end()) border->vertex = loop;
  return border;
}

// The border of a hole in the template, moved by `motion`.
std::shared_ptr<BorderLoop> movedHoleBorder(const MeshPtr& full, const RigidMotion& motion) {
  return innerLoop(moved(withHole(full->surface, kHoleCentre, kHoleRadius), motion), 0);
}

RigidMotion motion(double degrees, const Eigen::Vector3d& axis, const Eigen::Vector3d& shift) {
  RigidMotion m;
  m.rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()).matrix();
  m.translation = shift;
  return m;
}

// A turn by `degrees` about `axis` through the centroid of the hole's border, then a small shift.
RigidMotion turnAboutTheHole(const MeshPtr& full, double degrees, const Eigen::Vector3d& axis) {
  const auto border = movedHoleBorder(full, RigidMotion());
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v : border->vertex)
    centre += pointOf(border->mesh->surface, v) / double(border->vertex.size());
  RigidMotion turn = motion(degrees, axis, Eigen::Vector3d::Zero());
  turn.translation = centre - turn.rotation * centre + Eigen::Vector3d(0.01, -0.006, 0.008);
  return turn;
}

double maxDifference(const TriMesh& a, const TriMesh& b) {
  double most = 0;
  for (const auto v : a.vertices())
    most = std::max(most, (pointOf(a, v) - pointOf(b, v)).norm());
  return most;
}

// The node from where the template lies (prealign off), unless `params` says otherwise: these
// cases start near the truth.
test::NodeRun runIcp(const MeshPtr& mesh, const BorderLoopPtr& border, ParamMap params = {}) {
  params.try_emplace("prealign", false);
  return test::runNode("geobrush.template_icp", {{"template", mesh}, {"border", border}}, params);
}

std::string whereRefused(const MeshPtr& mesh, const BorderLoopPtr& border,
                         const ParamMap& params = {}) {
  try {
    runIcp(mesh, border, params);
  } catch (const NodeError& e) {
    return e.where();
  }
  return "(accepted)";
}

std::vector<Eigen::Vector3d> spread(const Eigen::Vector3d& scale) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 20; ++i) {
    const double s = double(i);
    points.push_back(scale.cwiseProduct(
        Eigen::Vector3d(std::sin(1.3 * s), std::cos(2.1 * s), std::sin(0.7 * s))));
  }
  return points;
}

TEST(FitRigidMotion, RecoversAMotionFromExactPairs) {
  const RigidMotion truth = motion(137, {1, -2, 0.5}, {3, -1, 2});
  const auto from = spread({1, 2, 3});
  std::vector<Eigen::Vector3d> to;
  for (const auto& p : from)
    to.push_back(truth(p));
  const RigidMotion fit = fitRigidMotion(from, to);
  EXPECT_LT((fit.rotation - truth.rotation).norm(), 1e-12);
  EXPECT_LT((fit.translation - truth.translation).norm(), 1e-12);
  EXPECT_NEAR(fit.angleDegrees(), 137, 1e-10);
}

// Points on the axes, spread most along x and least along z, mirrored in x: the best orthogonal
// map is the mirror (det -1); the best rotation keeps x mirrored and turns the least-spread z
// axis instead: the half turn about y.
TEST(FitRigidMotion, GivesTheBestRotationWhereAReflectionFitsBetter) {
  const std::vector<Eigen::Vector3d> from = {{3, 0, 0},  {-3, 0, 0}, {0, 2, 0},
                                             {0, -2, 0}, {0, 0, 1},  {0, 0, -1}};
  std::vector<Eigen::Vector3d> to;
  for (const auto& p : from)
    to.emplace_back(-p.x(), p.y(), p.z());
  const RigidMotion fit = fitRigidMotion(from, to);
  const Eigen::Matrix3d halfTurnAboutY = Eigen::Vector3d(-1, 1, -1).asDiagonal();
  EXPECT_LT((fit.rotation - halfTurnAboutY).norm(), 1e-12) << fit.rotation;
  EXPECT_LT(fit.translation.norm(), 1e-12);
}

// Coplanar points fix the rotation although the covariance has rank 2: its third singular
// vectors have arbitrary signs, which must not turn the answer into the mirror in the plane.
TEST(FitRigidMotion, RecoversARotationFromCoplanarPoints) {
  const auto from = spread({2, 1, 0});
  for (double degrees : {10.0, 95.0, 170.0}) {
    const RigidMotion truth = motion(degrees, {0.3, 1, -0.2}, {0.5, 0, -1});
    std::vector<Eigen::Vector3d> to;
    for (const auto& p : from)
      to.push_back(truth(p));
    const RigidMotion fit = fitRigidMotion(from, to);
    EXPECT_LT((fit.rotation - truth.rotation).norm(), 1e-12) << degrees;
    EXPECT_LT((fit.translation - truth.translation).norm(), 1e-12) << degrees;
  }
}

// U1: the border of a hole, turned under 20 degrees and shifted, against the template it was cut
// from: ICP recovers the motion in a few rounds, each border vertex paired with its own template
// vertex.
TEST(TemplateIcpNode, RecoversAKnownMotionOfTheBorder) {
  const MeshPtr full = templateMesh();
  for (const auto& [degrees, axis] :
       {std::pair{19.0, Eigen::Vector3d(1, 2, 3)}, std::pair{15.0, Eigen::Vector3d(0, 0, 1)}}) {
    const RigidMotion truth = turnAboutTheHole(full, degrees, axis);
    const auto border = movedHoleBorder(full, truth);
    ASSERT_GE(border->vertex.size(), 12u);
    const auto run = runIcp(full, border);
    const auto aligned = run.get<Mesh>("template");
    const auto pairs = run.get<PointPairs>("pairs");
    const auto report = run.get<Metrics>("report");
    ASSERT_TRUE(aligned && pairs && report);
    EXPECT_LT(maxDifference(aligned->surface, moved(full->surface, truth)), 1e-9) << degrees;
    EXPECT_EQ(pairs->templateVertex, border->vertex) << degrees;
    EXPECT_EQ(report->values.at("pairs_rejected"), 0);
    EXPECT_GT(report->values.at("rms_before"), 0.05);
    EXPECT_LT(report->values.at("rms_after"), 1e-9);
    EXPECT_NEAR(report->values.at("rotation_degrees"), degrees, 1e-9);
    EXPECT_NEAR(report->values.at("translation"), truth.translation.norm(), 1e-9);
    // More than one round (the first pairs are not all right), and the last finds no change.
    EXPECT_GE(report->values.at("iterations"), 3);
    EXPECT_LE(report->values.at("iterations"), 5);
    ASSERT_EQ(pairs->border.size(), border->vertex.size());
    for (std::size_t i = 0; i < border->vertex.size(); ++i)
      EXPECT_EQ(pairs->border[i], pointOf(border->mesh->surface, border->vertex[i]));
  }
}

TEST(TemplateIcpNode, StopsAfterTheGivenIterationsAndIsDeterministic) {
  const MeshPtr full = templateMesh();
  const RigidMotion truth = turnAboutTheHole(full, 19, {1, 2, 3});
  const auto border = movedHoleBorder(full, truth);
  const auto first = runIcp(full, border, {{"iterations", std::int64_t(1)}});
  const auto again = runIcp(full, border, {{"iterations", std::int64_t(1)}});
  EXPECT_EQ(first.get<Metrics>("report")->values.at("iterations"), 1);
  EXPECT_GT(first.get<Metrics>("report")->values.at("rms_after"), 1e-3);
  for (const char* port : {"template", "pairs", "report"})
    EXPECT_EQ(first.outputs.at(port)->contentHash(), again.outputs.at(port)->contentHash()) << port;
  const auto none = runIcp(full, border, {{"iterations", std::int64_t(0)}});
  EXPECT_EQ(maxDifference(none.get<Mesh>("template")->surface, full->surface), 0);
  EXPECT_EQ(none.get<Metrics>("report")->values.at("rms_after"),
            none.get<Metrics>("report")->values.at("rms_before"));
}

// Explicit pairs fix the motion in one solve, whatever its size.
TEST(TemplateIcpNode, ExplicitPairsRecoverAnyMotionInOneStep) {
  const MeshPtr full = templateMesh();
  const RigidMotion truth = motion(160, {-1, 0.5, 2}, {4, 1, -3});
  const auto border = movedHoleBorder(full, truth);
  std::vector<double> rows;
  for (std::size_t i = 0; i < border->vertex.size(); i += 3) {
    rows.push_back(double(i));
    rows.push_back(border->vertex[i]);
  }
  const auto run = runIcp(full, border, {{"explicit_pairs", rows}});
  const auto pairs = run.get<PointPairs>("pairs");
  EXPECT_LT(maxDifference(run.get<Mesh>("template")->surface, moved(full->surface, truth)), 1e-9);
  EXPECT_EQ(run.get<Metrics>("report")->values.at("iterations"), 1);
  EXPECT_NEAR(run.get<Metrics>("report")->values.at("rotation_degrees"), 160, 1e-9);
  ASSERT_EQ(pairs->templateVertex.size(), rows.size() / 2);
  for (std::size_t i = 0; i < pairs->templateVertex.size(); ++i)
    EXPECT_EQ(pairs->templateVertex[i], int(rows[2 * i + 1]));
}

// Two border vertices lifted far off the surface: with rejection they are left out of the fit
// and the motion is exact; kept, they pull it away. Either way every border point is paired.
TEST(TemplateIcpNode, RejectsOutlierPairs) {
  const MeshPtr full = templateMesh();
  const RigidMotion truth = turnAboutTheHole(full, 12, {2, -1, 1});
  TriMesh holed = withHole(full->surface, kHoleCentre, kHoleRadius);
  const auto loop = innerLoop(holed, 0)->vertex;
  const std::vector<std::size_t> lifted = {3, 11};
  for (std::size_t i : lifted) {
    const TriMesh::VertexHandle v(loop[i]);
    holed.set_point(v, holed.point(v) + TriMesh::Point(0, 0, 0.6));
  }
  const auto border = innerLoop(moved(holed, truth), 0);
  const auto run = runIcp(full, border);
  EXPECT_LT(maxDifference(run.get<Mesh>("template")->surface, moved(full->surface, truth)), 1e-9);
  EXPECT_EQ(run.get<Metrics>("report")->values.at("pairs_rejected"), 2);
  EXPECT_EQ(run.get<Metrics>("report")->values.at("pairs_kept"), double(loop.size() - 2));
  const auto& paired = run.get<PointPairs>("pairs")->templateVertex;
  ASSERT_EQ(paired.size(), loop.size());
  for (std::size_t i = 0; i < loop.size(); ++i) {
    if (i != lifted[0] && i != lifted[1]) {
      EXPECT_EQ(paired[i], loop[i]) << i;
    }
  }
  const auto kept = runIcp(full, border, {{"reject", 0.0}});
  EXPECT_GT(maxDifference(kept.get<Mesh>("template")->surface, moved(full->surface, truth)), 1e-3);
  EXPECT_EQ(kept.get<Metrics>("report")->values.at("pairs_rejected"), 0);
}

TEST(TemplateIcpNode, NamesThePortOrParamOfABadInput) {
  const MeshPtr full = templateMesh();
  const auto border = movedHoleBorder(full, RigidMotion());
  auto empty = std::make_shared<BorderLoop>();
  empty->mesh = border->mesh;
  EXPECT_EQ(whereRefused(full, empty), "input 'border'");
  auto notALoop = std::make_shared<BorderLoop>(*border);
  std::swap(notALoop->vertex[0], notALoop->vertex[1]);
  EXPECT_EQ(whereRefused(full, notALoop), "input 'border'");
  EXPECT_EQ(whereRefused(std::make_shared<const Mesh>(), border), "input 'template'");
  const double outside = double(full->surface.n_vertices());
  EXPECT_EQ(whereRefused(full, border, {{"explicit_pairs", std::vector<double>{0, outside}}}),
            "param 'explicit_pairs'");
  const double past = double(border->vertex.size());
  EXPECT_EQ(whereRefused(full, border, {{"explicit_pairs", std::vector<double>{past, 0}}}),
            "param 'explicit_pairs'");
  EXPECT_EQ(whereRefused(full, border, {{"explicit_pairs", std::vector<double>{0, 1.5}}}),
            "param 'explicit_pairs'");
  EXPECT_EQ(whereRefused(full, border, {{"explicit_pairs", std::vector<double>{0, 1, 0, 2}}}),
            "param 'explicit_pairs'");
  EXPECT_EQ(whereRefused(full, border, {{"reject", 0.5}}), "param 'reject'");
}

// The bunny's hole border against the patch cut out of it, moved a little: ICP lays the patch
// back where it was, its border vertices on the border's.
TEST(TemplateIcpNode, PutsTheRemovedBunnyPatchBackIntoItsHole) {
  const auto holed = readMesh(test::meshPath("cases/bunny_small_back_hole.obj")).mesh;
  const auto patch = readMesh(test::meshPath("cases/bunny_small_back_removed_patch.obj")).mesh;
  const auto loops = boundaryLoops(holed->surface);
  ASSERT_EQ(loops.size(), 1u);
  auto border = std::make_shared<BorderLoop>();
  border->mesh = holed;
  border->vertex = loops.front();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto v : patch->surface.vertices())
    centre += pointOf(patch->surface, v) / double(patch->surface.n_vertices());
  // 6 degrees about the patch's centre, then a shift of a tenth of the hole's radius.
  RigidMotion shift = motion(6, {1, -1, 2}, Eigen::Vector3d::Zero());
  shift.translation = centre - shift.rotation * centre + Eigen::Vector3d(0.08, -0.05, 0.06);
  const auto displaced = std::make_shared<const Mesh>(moved(patch->surface, shift));
  const auto run = runIcp(displaced, border);
  const auto report = run.get<Metrics>("report");
  EXPECT_LT(report->values.at("rms_after"), 1e-3 * report->values.at("rms_before"));
  EXPECT_LT(maxDifference(run.get<Mesh>("template")->surface, patch->surface), 1e-9);
  const auto pairs = run.get<PointPairs>("pairs");
  ASSERT_EQ(pairs->border.size(), border->vertex.size());
  for (std::size_t i = 0; i < pairs->border.size(); ++i)
    EXPECT_EQ(pointOf(patch->surface, pairs->templateVertex[i]), pairs->border[i]) << i;
  // With the frame alignment on as well, the same result.
  const auto both = runIcp(displaced, border, {{"prealign", true}});
  EXPECT_LT(maxDifference(both.get<Mesh>("template")->surface, patch->surface), 1e-9);
}

// A flat grid of n x n squares of side h centred on the origin, facing +z; faces whose centroid
// lies within `hole` of the centre are left out.
TriMesh centredGrid(int n, double h, double hole = 0) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      v.push_back(mesh.add_vertex(TriMesh::Point((x - n / 2.0) * h, (y - n / 2.0) * h, 0)));
  const auto at = [&](int x, int y) { return v[std::size_t(y * (n + 1) + x)]; };
  const auto add = [&](TriMesh::VertexHandle a, TriMesh::VertexHandle b, TriMesh::VertexHandle c) {
    const auto centroid = (mesh.point(a) + mesh.point(b) + mesh.point(c)) / 3;
    if (centroid.norm() >= hole) mesh.add_face(a, b, c);
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      add(at(x, y), at(x + 1, y), at(x + 1, y + 1));
      add(at(x, y), at(x + 1, y + 1), at(x, y + 1));
    }
  mesh.garbage_collection();
  return mesh;
}

// A plane template made at the origin and a hole in a tilted, moved plane: the frame alignment
// brings the template into the hole's plane, facing the surface's way, and ICP keeps it there
// (the start where the plane lies ends far from the hole).
TEST(TemplateIcpNode, PrealignPutsAPlaneMadeAtTheOriginIntoATiltedHole) {
  const RigidMotion placed = motion(35, {1, 1, 0}, {5, -3, 2});
  auto holed = std::make_shared<Mesh>(moved(centredGrid(24, 0.1, 0.5), placed));
  const auto loops = boundaryLoops(holed->surface);
  ASSERT_EQ(loops.size(), 2u);  // the grid's rim and the hole
  auto border = std::make_shared<BorderLoop>();
  border->mesh = holed;
  for (const auto& loop : loops)
    if (border->vertex.empty() || loop.size() < border->vertex.size()) border->vertex = loop;
  const auto plane = std::make_shared<const Mesh>(centredGrid(30, 0.04));
  const auto run = runIcp(plane, border, {{"prealign", true}});
  const auto aligned = run.get<Mesh>("template");
  ASSERT_TRUE(aligned);
  const Eigen::Vector3d normal = placed.rotation * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d origin = placed.translation;
  for (const auto v : aligned->surface.vertices())
    ASSERT_LT(std::abs((pointOf(aligned->surface, v) - origin).dot(normal)), 1e-9);
  const auto f = *aligned->surface.faces().begin();
  std::vector<Eigen::Vector3d> c;
  for (const auto v : aligned->surface.fv_range(f))
    c.push_back(pointOf(aligned->surface, v));
  EXPECT_GT((c[1] - c[0]).cross(c[2] - c[0]).dot(normal), 0);  // facing the surface's way
  EXPECT_LT(run.get<Metrics>("report")->values.at("rms_after"), 0.04);
  EXPECT_EQ(run.get<Metrics>("report")->values.at("started_where_placed"), 0);
  // Without the frame alignment the template stays in the plane z = 0, far from the hole.
  const auto unaligned = runIcp(plane, border, {{"iterations", std::int64_t(0)}});
  EXPECT_GT(unaligned.get<Metrics>("report")->values.at("rms_after"), 1.0);
  EXPECT_TRUE(run.warnings.empty());  // finer than the border: one border point per vertex
  // A template coarser than the border pairs several border points with one vertex: warned.
  const auto coarse =
      runIcp(std::make_shared<const Mesh>(centredGrid(6, 0.2)), border, {{"prealign", true}});
  ASSERT_EQ(coarse.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(coarse.warnings[0], "coarser than the border"));
}

// A tall bump filling a hole in a plane, placed where it belongs: the frame alignment would sink
// it by its centroid's height, and ICP from there settles short of the truth; the start where
// it lies fits every border point exactly and wins.
TEST(TemplateIcpNode, PrealignKeepsATemplatePlacedInTheHoleWhereItIs) {
  const double radius = 0.5;
  auto holed = std::make_shared<Mesh>(centredGrid(24, 0.1, radius));
  const auto loops = boundaryLoops(holed->surface);
  auto border = std::make_shared<BorderLoop>();
  border->mesh = holed;
  for (const auto& loop : loops)
    if (border->vertex.empty() || loop.size() < border->vertex.size()) border->vertex = loop;
  // The grid's faces the hole left out, the inner vertices raised into a bump twice the radius.
  const TriMesh grid = centredGrid(24, 0.1);
  std::vector<int> inside;
  for (const auto f : grid.faces()) {
    const auto t = faceTriangle(grid, f.idx());
    if (((t[0] + t[1] + t[2]) / 3).norm() < radius) inside.push_back(f.idx());
  }
  TriMesh bump = extractSubmesh(grid, inside).surface;
  for (const auto v : bump.vertices()) {
    const Eigen::Vector3d p = pointOf(bump, v);
    if (!bump.is_boundary(v)) bump.set_point(v, toPoint(p + Eigen::Vector3d(0, 0, 2 * radius)));
  }
  const auto placed = std::make_shared<const Mesh>(bump);
  const auto run = runIcp(placed, border, {{"prealign", true}});
  const auto report = run.get<Metrics>("report");
  EXPECT_EQ(report->values.at("started_where_placed"), 1);
  EXPECT_LT(report->values.at("rms_all_pairs"), 1e-12);
  EXPECT_LT(maxDifference(run.get<Mesh>("template")->surface, bump), 1e-12);
  // From the frame alignment alone the fit ends away from the border.
  geobrush::TemplateIcpOptions options;
  options.initial = frameAlignment(bump, holed->surface, border->vertex);
  const PointNeighbours tree(vertexPoints(bump));
  std::vector<Eigen::Vector3d> points;
  for (int v : border->vertex)
    points.push_back(pointOf(holed->surface, v));
  EXPECT_GT(alignTemplate(tree, points, options).rmsAllPairs, 0.01);
}

}  // namespace
}  // namespace geobrush
