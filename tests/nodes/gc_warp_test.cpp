#include "gc_warp.hpp"

#include <gtest/gtest.h>

#include <set>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

std::vector<Eigen::Vector3d> meshPoints(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> points;
  for (auto v : mesh.vertices())
    points.push_back(toEigen(mesh.point(v)));
  return points;
}

TriMesh mapCage(const TriMesh& cage,
                const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& f) {
  TriMesh out = cage;
  for (auto v : out.vertices()) {
    const Eigen::Vector3d q = f(toEigen(out.point(v)));
    out.set_point(v, toPoint(q));
  }
  return out;
}

TriMesh flipped(const TriMesh& cage) {
  TriMesh out;
  for (auto v : cage.vertices())
    out.add_vertex(cage.point(v));
  for (const auto& f : test::faceIndices(cage))
    out.add_face(TriMesh::VertexHandle(f[0]), TriMesh::VertexHandle(f[2]),
                 TriMesh::VertexHandle(f[1]));
  return out;
}

std::vector<Eigen::Vector3d> randomPoints(std::mt19937& rng, int count, double radius, bool ball) {
  std::uniform_real_distribution<double> u(-radius, radius);
  std::vector<Eigen::Vector3d> points;
  while (int(points.size()) < count) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    if (!ball || p.norm() <= radius) points.push_back(p);
  }
  return points;
}

// Max over points of |sum_i phi_i v_i + sum_j psi_j n_j - x|: linear precision.
double reproductionError(const GreenCoordinatesResult& gc, const TriMesh& cage,
                         const std::vector<Eigen::Vector3d>& points) {
  const auto mapped = applyGreenCoordinates(gc.phi, gc.psi, cage, cage);
  double error = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    error = std::max(error, (mapped[i] - points[i]).norm());
  return error;
}

struct NamedCage {
  const char* name;
  TriMesh mesh;
  double radius;  // of the region sampled inside
  bool ball;
};

std::vector<NamedCage> cages() {
  return {{"cube", test::boxCage({-1, -1, -1}, {1, 1, 1}, 1), 0.95, false},
          {"icosphere", test::icosphere(1), 0.85, true}};
}

TEST(GreenCoordinates, TestCagesAreClosedAndOutward) {
  for (const auto& c : cages()) {
    EXPECT_GT(test::signedVolume(c.mesh), 0) << c.name;
    EXPECT_EQ(test::topology(c.mesh).boundaryHalfedges, 0u) << c.name;
  }
  EXPECT_EQ(cages()[0].mesh.n_faces(), 12u);
  EXPECT_EQ(cages()[1].mesh.n_faces(), 80u);
}

TEST(GreenCoordinates, PartitionOfUnityAndLinearPrecision) {
  std::mt19937 rng(7);
  for (const auto& c : cages()) {
    const auto points = randomPoints(rng, 200, c.radius, c.ball);
    const auto gc = computeGreenCoordinates(c.mesh, points);
    EXPECT_TRUE(gc.outsidePoints.empty()) << c.name;
    ASSERT_TRUE(gc.phi.allFinite() && gc.psi.allFinite()) << c.name;
    EXPECT_LE((gc.phi.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-9) << c.name;
    EXPECT_LE(reproductionError(gc, c.mesh, points), 1e-9) << c.name;
    EXPECT_GE(gc.psi.minCoeff(), 0) << c.name;  // -int G with G = -1/(4 pi r) < 0
  }
}

TEST(GreenCoordinates, SimilarityOfTheCageMovesThePointsAlike) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const auto& c : cages()) {
    const auto points = randomPoints(rng, 100, c.radius, c.ball);
    const auto gc = computeGreenCoordinates(c.mesh, points);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
      const Eigen::Matrix3d rotation =
          Eigen::AngleAxisd(std::numbers::pi * u(rng), axis).toRotationMatrix();
      const double scale = std::exp(u(rng));  // 0.37 .. 2.7
      const Eigen::Vector3d shift(3 * u(rng), 3 * u(rng), 3 * u(rng));
      auto similarity = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
        return scale * rotation * x + shift;
      };
      const TriMesh moved = mapCage(c.mesh, similarity);
      EXPECT_LE((greenStretch(c.mesh, moved).array() - scale).abs().maxCoeff(), 1e-12);
      const auto mapped = applyGreenCoordinates(gc.phi, gc.psi, c.mesh, moved);
      for (std::size_t i = 0; i < points.size(); ++i)
        ASSERT_LE((mapped[i] - similarity(points[i])).norm(), 1e-9)
            << c.name << " trial " << trial << " point " << i;
    }
  }
}

// Progress rises to 1 on the calling thread, and reporting it changes no bit of the result.
TEST(GreenCoordinates, ReportsProgressWithoutChangingTheResult) {
  std::mt19937 rng(5);
  const auto all = cages();
  const auto& c = all[1];
  const auto points = randomPoints(rng, 3000, c.radius, c.ball);
  std::vector<double> reports;
  GreenOptions options;
  options.progress = [&](double fraction) { reports.push_back(fraction); };
  const auto reported = computeGreenCoordinates(c.mesh, points, options);
  const auto quiet = computeGreenCoordinates(c.mesh, points);
  ASSERT_FALSE(reports.empty());
  EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
  EXPECT_EQ(reports.back(), 1.0);
  EXPECT_TRUE(reported.phi == quiet.phi);
  EXPECT_TRUE(reported.psi == quiet.psi);
  // A progress callback that throws (a cancelled evaluation) stops the computation.
  options.progress = [](double fraction) {
    if (fraction > 0.1) throw std::runtime_error("cancelled");
  };
  EXPECT_THROW(computeGreenCoordinates(c.mesh, points, options), std::runtime_error);
}

TEST(GreenCoordinates, RefusesBadCages) {
  const TriMesh cube = test::boxCage({-1, -1, -1}, {1, 1, 1}, 2);
  const std::vector<Eigen::Vector3d> points = {Eigen::Vector3d::Zero()};
  EXPECT_THROW(computeGreenCoordinates(flipped(cube), points), CageError);
  EXPECT_THROW(computeGreenCoordinatesNaive(flipped(cube), points), CageError);
  try {
    computeGreenCoordinates(flipped(cube), points);
  } catch (const CageError& e) {
    EXPECT_TRUE(test::contains(e.what(), "inward"));
  }
  TriMesh open = cube;
  open.request_face_status();
  open.delete_face(TriMesh::FaceHandle(0), false);
  open.garbage_collection();
  EXPECT_THROW(computeGreenCoordinates(open, points), CageError);

  const auto gc = computeGreenCoordinates(cube, points);
  const TriMesh other = test::boxCage({-1, -1, -1}, {1, 1, 1}, 3);
  EXPECT_THROW(applyGreenCoordinates(gc.phi, gc.psi, cube, other), CageError);
  EXPECT_THROW(applyGreenCoordinates(gc.phi, gc.psi, cube, flipped(cube)), CageError);
}

TEST(GreenCoordinates, ApplyingToSomeRowsGivesThoseRowsOfTheWhole) {
  const TriMesh cage = test::boxCage({-1, -1, -1}, {1, 1, 1}, 3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 40; ++i)
    points.emplace_back(std::sin(i), std::cos(3 * i) * 0.9, 0.02 * i - 0.5);
  const auto gc = computeGreenCoordinates(cage, points);
  TriMesh moved = cage;
  for (auto v : moved.vertices())
    moved.set_point(v, moved.point(v) * 1.3 + TriMesh::Point(0.2 * moved.point(v)[1], 0, 0));
  const auto whole = applyGreenCoordinates(gc.phi, gc.psi, cage, moved);
  const std::vector<int> rows = {7, 0, 39, 7, 12};
  const auto some = applyGreenCoordinates(gc.phi, gc.psi, cage, moved, rows);
  ASSERT_EQ(some.size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
    EXPECT_EQ(some[k], whole[std::size_t(rows[k])]) << k;
  EXPECT_THROW(applyGreenCoordinates(gc.phi, gc.psi, cage, moved, std::vector<int>{40}), CageError);
  EXPECT_THROW(applyGreenCoordinates(gc.phi, gc.psi, cage, moved, std::vector<int>{-1}), CageError);
}

TEST(GreenCoordinates, ReportsPointsOutside) {
  const TriMesh cube = test::boxCage({-1, -1, -1}, {1, 1, 1}, 1);
  const auto gc = computeGreenCoordinates(cube, {{0, 0, 0}, {3, 0, 0}, {0.5, 0.5, 0.5}});
  EXPECT_EQ(gc.outsidePoints, std::vector<int>{1});
}

// Points at distances 1e-12 .. 1e-6 inside from a face, an edge and a vertex, and on them. With
// the default epsilon those within 1e-8 of the cage's size are snapped onto it (their interior
// limit); those farther off lose about 1e-17 / distance to rounding, so 1e-9 holds for both.
TEST(GreenCoordinates, PointsNearTheCageStayFiniteAndExact) {
  for (const auto& c : cages()) {
    const TriMesh& cage = c.mesh;
    const auto faces = test::faceIndices(cage);
    const auto corners = meshPoints(cage);
    const auto& f = faces[3];
    const Eigen::Vector3d a = corners[std::size_t(f[0])], b = corners[std::size_t(f[1])],
                          d = corners[std::size_t(f[2])];
    const Eigen::Vector3d inward = -(b - a).cross(d - a).normalized();
    std::vector<std::pair<const char*, Eigen::Vector3d>> anchors = {
        {"face", (a + b + d) / 3}, {"edge", 0.7 * a + 0.3 * b}, {"vertex", a}};
    std::vector<Eigen::Vector3d> points;
    for (const auto& [where, anchor] : anchors) {
      // Toward the centre stays inside these convex cages near a vertex or an edge as well.
      const Eigen::Vector3d direction =
          std::string(where) == "face" ? inward : (-anchor).normalized();
      for (double distance : {0.0, 1e-12, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6})
        points.push_back(anchor + distance * direction);
    }
    for (const auto& gc :
         {computeGreenCoordinates(cage, points), computeGreenCoordinatesNaive(cage, points)}) {
      ASSERT_TRUE(gc.phi.allFinite() && gc.psi.allFinite()) << c.name;
      EXPECT_TRUE(gc.outsidePoints.empty()) << c.name;
      EXPECT_LE((gc.phi.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-9) << c.name;
      const auto mapped = applyGreenCoordinates(gc.phi, gc.psi, cage, cage);
      for (std::size_t i = 0; i < points.size(); ++i)
        EXPECT_LE((mapped[i] - points[i]).norm(), 1e-9)
            << c.name << " " << anchors[i / 7].first << " point " << i % 7;
    }
  }
}

TEST(GreenCoordinates, FastEqualsNaiveAndIgnoresThreadCount) {
  std::mt19937 rng(3);
  const TriMesh cage =
      mapCage(test::boxCage({-1, -1, -1}, {1, 1, 1}, 3), [](const Eigen::Vector3d& x) {
        return Eigen::Vector3d(x.x() * (1 + 0.2 * x.y()), x.y(), x.z() + 0.1 * x.x() * x.x());
      });
  ASSERT_GT(test::signedVolume(cage), 0);
  const auto points = randomPoints(rng, 300, 0.8, false);
  const auto naive = computeGreenCoordinatesNaive(cage, points);
  GreenOptions options;
  options.threads = 1;
  const auto one = computeGreenCoordinates(cage, points, options);
  EXPECT_LE((one.phi - naive.phi).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((one.psi - naive.psi).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(reproductionError(one, cage, points), 1e-9);
  for (int threads : {2, 3, 8}) {
    options.threads = threads;
    const auto many = computeGreenCoordinates(cage, points, options);
    EXPECT_TRUE((many.phi.array() == one.phi.array()).all()) << threads << " threads";
    EXPECT_TRUE((many.psi.array() == one.psi.array()).all()) << threads << " threads";
  }
}

// A patch of the bunny in a subdivided box cage, bent smoothly.
TEST(GreenCoordinates, WarpsAPatchOfARealMesh) {
  const auto bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto all = meshPoints(bunny->surface);
  const Eigen::Vector3d centre = all[all.size() / 2];
  Eigen::AlignedBox3d whole;
  for (const auto& p : all)
    whole.extend(p);
  const double radius = 0.25 * whole.diagonal().norm();
  std::vector<Eigen::Vector3d> patch;
  Eigen::AlignedBox3d box;
  for (const auto& p : all)
    if ((p - centre).norm() < radius) {
      patch.push_back(p);
      box.extend(p);
    }
  ASSERT_GT(patch.size(), 100u);
  const Eigen::Vector3d margin = 0.1 * box.sizes() + Eigen::Vector3d::Constant(1e-3);
  const TriMesh cage = test::boxCage(box.min() - margin, box.max() + margin, 4);
  const auto gc = computeGreenCoordinates(cage, patch);
  EXPECT_TRUE(gc.outsidePoints.empty());
  ASSERT_TRUE(gc.phi.allFinite() && gc.psi.allFinite());
  const double size = (box.max() - box.min() + 2 * margin).norm();
  EXPECT_LE(reproductionError(gc, cage, patch), 1e-9 * size);

  // Bend about the z axis: the angle grows with x, so straight lines along x become arcs.
  const Eigen::Vector3d lo = box.min() - margin, span = box.sizes() + 2 * margin;
  const TriMesh bent = mapCage(cage, [&](const Eigen::Vector3d& x) {
    const double angle = 0.5 * (x.x() - lo.x()) / span.x();
    const double r = x.y() - lo.y() + span.y();
    return Eigen::Vector3d(lo.x() + r * std::sin(angle), lo.y() + r * std::cos(angle) - span.y(),
                           x.z());
  });
  const auto warped = applyGreenCoordinates(gc.phi, gc.psi, cage, bent);
  Eigen::AlignedBox3d bentBox;
  for (auto v : bent.vertices())
    bentBox.extend(toEigen(bent.point(v)));
  double moved = 0;
  for (const auto& p : warped) {
    ASSERT_TRUE(p.allFinite());
    EXPECT_LE(bentBox.exteriorDistance(p), 0.05 * size);
  }
  for (std::size_t i = 0; i < patch.size(); ++i)
    moved = std::max(moved, (warped[i] - patch[i]).norm());
  EXPECT_GT(moved, 0.01 * size);
}

using test::DirectContext;

std::shared_ptr<const Cage> cageValue(TriMesh mesh) {
  auto cage = std::make_shared<Cage>();
  cage->mesh = std::move(mesh);
  return cage;
}

std::shared_ptr<const Canvas> gridCanvas(int n) {
  auto canvas = std::make_shared<Canvas>();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      canvas->surface.add_vertex(
          {-0.5 + double(i) / n, -0.5 + double(j) / n, 0.1 * std::sin(3.0 * i / n)});
  auto at = [&](int i, int j) { return TriMesh::VertexHandle(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      canvas->surface.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      canvas->surface.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return canvas;
}

TEST(GcWarpNode, DerivesTheCoordinatesOnceWhileOnlyTheTargetCageMoves) {
  const NodeType* type = test::registry().find("geobrush.gc_warp");
  ASSERT_NE(type, nullptr) << (test::registryLoadErrors().empty() ? ""
                                                                  : test::registryLoadErrors()[0]);
  const auto canvas = gridCanvas(6);
  const TriMesh box = test::boxCage({-1, -1, -1}, {1, 1, 1}, 2);
  const auto source = cageValue(box);
  const auto node = type->create();
  // The framework's derived data, kept from one compute to the next as an evaluator keeps it.
  const auto derived = std::make_shared<DerivedStore>();

  auto run = [&](std::shared_ptr<const Canvas> c, std::shared_ptr<const Cage> s,
                 std::shared_ptr<const Cage> t) {
    DirectContext ctx(*type, {{"canvas", c}, {"source_cage", s}, {"target_cage", t}}, {}, derived);
    node->compute(ctx);
    EXPECT_TRUE(ctx.warnings.empty());
    return std::pair(std::dynamic_pointer_cast<const GreenCoordinates>(ctx.outputs["coordinates"]),
                     std::dynamic_pointer_cast<const Mesh>(ctx.outputs["draft"]));
  };
  const auto [first, identity] = run(canvas, source, source);
  ASSERT_NE(first, nullptr);
  ASSERT_NE(identity, nullptr);
  EXPECT_EQ(first->phi.rows(), Eigen::Index(canvas->surface.n_vertices()));
  EXPECT_EQ(first->cage, source);
  for (auto v : canvas->surface.vertices())
    EXPECT_LE((identity->surface.point(v) - canvas->surface.point(v)).norm(), 1e-12);
  EXPECT_EQ(test::faceIndices(identity->surface), test::faceIndices(canvas->surface));

  auto twist = [](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    return Eigen::AngleAxisd(0.4 * x.z(), Eigen::Vector3d::UnitZ()) * x + Eigen::Vector3d(0, 0, 1);
  };
  const auto target = cageValue(mapCage(box, twist));
  const auto [second, draft] = run(canvas, cageValue(box), target);
  // The same value, not a recomputation: an equal source cage in a new value counts as equal.
  EXPECT_EQ(second, first);
  const auto expected = applyGreenCoordinates(first->phi, first->psi, box, target->mesh);
  for (auto v : draft->surface.vertices())
    EXPECT_EQ(toEigen(draft->surface.point(v)), expected[std::size_t(v.idx())]);

  const auto [third, unused] =
      run(canvas, cageValue(test::boxCage({-1, -1, -1}, {1, 1, 2}, 2)), target);
  EXPECT_NE(third, first);
  const auto [fourth, unused2] = run(gridCanvas(5), source, source);
  EXPECT_NE(fourth, third);
}

// With a region connected, the node warps the region's draft support alone, keeps the rows
// warped for the same target cage and reuses a draft value nothing holds any more: over dabs
// (the support grows and shrinks) and cage moves, with values held or let go, each draft is the
// support warped and every other vertex at its source position, bit for bit.
TEST(GcWarpNode, APartialDraftIsTheSupportWarpedWhateverCameBefore) {
  const NodeType* type = test::registry().find("geobrush.gc_warp");
  ASSERT_NE(type, nullptr);
  const auto canvas = gridCanvas(12);
  const TriMesh box = test::boxCage({-1, -1, -1}, {1, 1, 1}, 2);
  const auto source = cageValue(box);
  const auto node = type->create();
  const auto coordinates = computeGreenCoordinates(box, [&] {
    std::vector<Eigen::Vector3d> points;
    for (auto v : canvas->surface.vertices())
      points.push_back(toEigen(canvas->surface.point(v)));
    return points;
  }());
  const auto derived = std::make_shared<DerivedStore>();  // kept across steps, as by an evaluator
  const auto bin = std::make_shared<RecycleBin>();        // where each step's draft is retired
  std::vector<std::shared_ptr<const Mesh>> held;
  std::set<const Mesh*> values;
  for (int step = 0; step < 10; ++step) {
    SCOPED_TRACE(step);
    // Moves of the target cage at steps 4 and 7; the support a growing, then shrinking disc.
    const double shift = 0.1 * (step >= 4) + 0.05 * (step >= 7);
    const auto target = cageValue(mapCage(box, [shift](const Eigen::Vector3d& x) {
      return Eigen::Vector3d(x.x() + shift, x.y() * (1 + shift), x.z());
    }));
    const double radius = 0.15 + 0.05 * (step < 6 ? step : 10 - step);
    auto region = std::make_shared<Region2D>();
    for (auto v : canvas->surface.vertices())
      if (Eigen::Vector2d(canvas->surface.point(v)[0], canvas->surface.point(v)[1]).norm() < radius)
        region->draftSupport.push_back(v.idx());
    DirectContext ctx(
        *type,
        {{"canvas", canvas}, {"source_cage", source}, {"target_cage", target}, {"region", region}},
        {}, derived, bin);
    node->compute(ctx);
    const auto draft = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["draft"]);
    ASSERT_NE(draft, nullptr);
    values.insert(draft.get());
    if (step % 3 == 0) held.push_back(draft);  // the others are let go at once
    const auto warped = applyGreenCoordinates(coordinates.phi, coordinates.psi, box, target->mesh,
                                              region->draftSupport);
    std::vector<Eigen::Vector3d> expected;
    for (auto v : canvas->surface.vertices())
      expected.push_back(toEigen(canvas->surface.point(v)));
    for (std::size_t k = 0; k < warped.size(); ++k)
      expected[std::size_t(region->draftSupport[k])] = warped[k];
    for (auto v : draft->surface.vertices())
      ASSERT_EQ(toEigen(draft->surface.point(v)), expected[std::size_t(v.idx())]) << v.idx();
    EXPECT_EQ(test::faceIndices(draft->surface), test::faceIndices(canvas->surface));
  }
  // Values let go were recycled: fewer values than steps.
  EXPECT_LT(values.size(), 10u);
}

TEST(GcWarpNode, NamesThePortOfABadCage) {
  const NodeType* type = test::registry().find("geobrush.gc_warp");
  ASSERT_NE(type, nullptr);
  const TriMesh box = test::boxCage({-1, -1, -1}, {1, 1, 1}, 2);
  auto error = [&](const TriMesh& source, const TriMesh& target) -> std::string {
    DirectContext ctx(*type, {{"canvas", gridCanvas(3)},
                              {"source_cage", cageValue(source)},
                              {"target_cage", cageValue(target)}});
    try {
      type->create()->compute(ctx);
    } catch (const NodeError& e) {
      return e.where() + ": " + e.what();
    }
    return "(no error)";
  };
  EXPECT_TRUE(test::contains(error(flipped(box), box), "input 'source_cage': "));
  EXPECT_TRUE(test::contains(error(box, test::boxCage({-1, -1, -1}, {1, 1, 1}, 3)),
                             "input 'target_cage': "));
}

}  // namespace
}  // namespace geobrush
