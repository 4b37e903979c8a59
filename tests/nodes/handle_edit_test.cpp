#include "handle_edit.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <set>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/node.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// The n x n grid over [-1, 1]^2 at z = 0, two triangles per square; n odd puts a vertex at the
// centre. Its boundary is the square's rim.
TriMesh grid(int n) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      v.push_back(mesh.add_vertex({-1 + 2.0 * i / (n - 1), -1 + 2.0 * j / (n - 1), 0}));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto a = v[std::size_t(j * n + i)];
      const auto b = v[std::size_t(j * n + i + 1)];
      const auto c = v[std::size_t((j + 1) * n + i + 1)];
      const auto d = v[std::size_t((j + 1) * n + i)];
      mesh.add_face(a, b, c);
      mesh.add_face(a, c, d);
    }
  return mesh;
}

constexpr int kGrid = 41;

int gridVertex(int i, int j) {
  return j * kGrid + i;
}

HandleEdit translation(const Eigen::Vector3d& point, double radius, const Eigen::Vector3d& t) {
  HandleEdit edit;
  edit.point = point;
  edit.radius = radius;
  edit.translation = t;
  return edit;
}

HandleEditResult editGrid(std::vector<HandleEdit> edits,
                          HandleShape profile = HandleProfile::Smoothstep) {
  HandleEditOptions options;
  options.profile = profile;
  options.edits = std::move(edits);
  return editTemplate(grid(kGrid), options);
}

// Every boundary vertex of `input` keeps its point, bit for bit.
void expectBoundaryBitIdentical(const TriMesh& input, const TriMesh& edited) {
  int boundary = 0;
  for (auto v : input.vertices()) {
    if (!input.is_boundary(v)) continue;
    ++boundary;
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(edited.point(v)[c], input.point(v)[c]) << "boundary vertex " << v.idx();
    }
  }
  EXPECT_GT(boundary, 0);
}

TriMesh readMesh(const std::string& name) {
  TriMesh mesh;
  if (!OpenMesh::IO::read_mesh(mesh, test::meshPath(name).string())) {
    ADD_FAILURE() << "cannot read " << name;
  }
  return mesh;
}

TEST(HandleEdit, ProfilesHaveTheirValuesAtZeroHalfAndOne) {
  for (HandleProfile p :
       {HandleProfile::Smoothstep, HandleProfile::Linear, HandleProfile::Cosine}) {
    EXPECT_EQ(profileValue(p, 0.0), 1.0);
    EXPECT_EQ(profileValue(p, 0.5), 0.5);
    EXPECT_EQ(profileValue(p, 1.0), 0.0);
  }
  EXPECT_NEAR(profileValue(HandleProfile::Smoothstep, 0.25), 1 - 3 * 0.0625 + 2 * 0.015625, 1e-15);
  EXPECT_NEAR(profileValue(HandleProfile::Linear, 0.25), 0.75, 1e-15);
  EXPECT_NEAR(profileValue(HandleProfile::Cosine, 0.25), (1 + std::sqrt(0.5)) / 2, 1e-15);
  EXPECT_EQ(parseHandleProfile("cosine"), HandleProfile::Cosine);
  try {
    parseHandleProfile("cubic");
    ADD_FAILURE() << "an unknown profile was accepted";
  } catch (const HandleEditError& e) {
    EXPECT_EQ(e.option(), "profile");
  }
}

// A custom profile is its samples joined by straight lines: {1, 0.5, 0} is the linear profile, a
// plateau {1, 1, 0} holds alpha at 1 to t = 1/2; bad samples are refused.
TEST(HandleEdit, ACustomProfileDrawsAlphaThroughItsSamples) {
  const HandleShape straight = customShape({1, 0.5, 0});
  const HandleShape plateau = customShape({1, 1, 0});
  for (int i = 0; i <= 20; ++i) {
    const double t = i / 20.0;
    EXPECT_NEAR(straight(t), profileValue(HandleProfile::Linear, t), 1e-15) << t;
    EXPECT_EQ(plateau(t), t <= 0.5 ? 1.0 : 2 * (1 - t)) << t;
  }
  EXPECT_EQ(plateau(0), 1.0);
  EXPECT_EQ(plateau(1), 0.0);
  for (const auto& bad : std::vector<std::vector<double>>{{1}, {0.9, 0}, {1, 0.1}, {1, NAN, 0}}) {
    try {
      customShape(bad);
      ADD_FAILURE() << "accepted " << bad.size() << " samples";
    } catch (const HandleEditError& e) {
      EXPECT_EQ(e.option(), "profile_samples");
    }
  }
}

// The centre raised by h with the plateau profile: on the ray to the rim t = x, so the points up
// to x = 1/2 rise by exactly h and the rest by h * 2 (1 - x); the rim stays.
TEST(HandleEdit, APlateauProfileMovesTheInnerHalfRigidly) {
  const double h = 0.3;
  const TriMesh flat = grid(kGrid);
  const auto result = editGrid({translation({0, 0, 0}, 0, {0, 0, h})}, customShape({1, 1, 0}));
  expectBoundaryBitIdentical(flat, result.mesh);
  for (int i = kGrid / 2; i < kGrid; ++i) {
    const double x = flat.point(TriMesh::VertexHandle(gridVertex(i, kGrid / 2)))[0];
    const double z = result.mesh.point(TriMesh::VertexHandle(gridVertex(i, kGrid / 2)))[2];
    if (x <= 0.5) {
      EXPECT_EQ(z, h) << x;
    } else {
      EXPECT_NEAR(z, h * 2 * (1 - x), 1e-12) << x;
    }
  }
}

TEST(HandleEdit, ReadsRowsAndNamesTheFirstBadOne) {
  const std::vector<double> rows = {1, 2, 3, 0.5, 4, 5, 6, 0, 0, 1, 30,
                                    7, 8, 9, 0.0, 0, 0, 1, 0, 0, 0, 0};
  const auto edits = editsFromRows(rows);
  ASSERT_EQ(edits.size(), 2u);
  EXPECT_EQ(edits[0].point, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(edits[0].radius, 0.5);
  EXPECT_EQ(edits[0].translation, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(edits[0].axis, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(edits[0].angleDegrees, 30);
  EXPECT_EQ(edits[1].point, Eigen::Vector3d(7, 8, 9));

  const auto expectError = [](std::vector<double> bad, const std::string& part) {
    try {
      editsFromRows(bad);
      ADD_FAILURE() << "accepted rows that should fail with " << part;
    } catch (const HandleEditError& e) {
      EXPECT_EQ(e.option(), "edits");
      EXPECT_TRUE(test::contains(e.what(), part));
    }
  };
  std::vector<double> good(rows.begin(), rows.begin() + 11);
  expectError(std::vector<double>(10, 0.0), "rows of 11");
  std::vector<double> nan = good;
  nan.insert(nan.end(), good.begin(), good.end());
  nan[11 + 5] = std::nan("");
  expectError(nan, "row 2");
  std::vector<double> negative = good;
  negative[3] = -0.1;
  expectError(negative, "row 1: the radius is negative");
  std::vector<double> noAxis = good;
  noAxis[7] = noAxis[8] = noAxis[9] = 0;
  expectError(noAxis, "row 1: a rotation needs a non-zero axis");
}

TEST(HandleEdit, TheRigidMapPreservesDistancesAndFixesItsPivot) {
  HandleEdit edit;
  edit.axis = {1, -2, 0.5};
  edit.angleDegrees = 37;
  const Eigen::Vector3d pivot(0.3, -0.2, 1.1);
  const RigidMotion turn = handleMotion(edit, pivot);
  EXPECT_LE((turn(pivot) - pivot).norm(), 1e-15);
  EXPECT_LE((turn.rotation.transpose() * turn.rotation - Eigen::Matrix3d::Identity()).norm(),
            1e-15);
  EXPECT_NEAR(turn.rotation.determinant(), 1.0, 1e-15);
  // A point on the axis through the pivot stays; the angle is the one asked for.
  const Eigen::Vector3d axis = edit.axis.normalized();
  EXPECT_LE((turn(pivot + 2 * axis) - (pivot + 2 * axis)).norm(), 1e-14);
  const Eigen::Vector3d across = axis.unitOrthogonal();
  EXPECT_NEAR(std::acos((turn(pivot + across) - pivot).dot(across)), 37 * std::numbers::pi / 180,
              1e-12);

  edit.translation = {1, 2, -3};
  const RigidMotion move = handleMotion(edit, pivot);
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {1, 2, 3}, {-4, 0.5, 2}, {0.1, -7, 1}};
  for (const auto& p : points)
    for (const auto& q : points) {
      EXPECT_NEAR((move(p) - move(q)).norm(), (p - q).norm(), 1e-12);
    }
  EXPECT_LE((move(pivot) - (pivot + edit.translation)).norm(), 1e-14);

  // Without a rotation, T adds exactly the translation.
  HandleEdit shift;
  shift.translation = {0.1, -0.2, 0.3};
  const RigidMotion t = handleMotion(shift, pivot);
  for (const auto& p : points) {
    EXPECT_EQ(t(p), p + shift.translation);
  }
}

TEST(HandleEdit, ACentrePointRaisedByHRisesExactlyHAndTheRimStays) {
  const double h = 0.3;
  const TriMesh flat = grid(kGrid);
  const auto result = editGrid({translation({0, 0, 0}, 0, {0, 0, h})});
  const TriMesh& raised = result.mesh;
  const int centre = gridVertex(kGrid / 2, kGrid / 2);
  EXPECT_EQ(raised.point(TriMesh::VertexHandle(centre))[2], h);
  expectBoundaryBitIdentical(flat, raised);
  // Heights fall strictly along a ray from the centre to the rim (smoothstep), x and y stay.
  double previous = h;
  for (int i = kGrid / 2 + 1; i < kGrid; ++i) {
    const auto p = raised.point(TriMesh::VertexHandle(gridVertex(i, kGrid / 2)));
    const auto q = flat.point(TriMesh::VertexHandle(gridVertex(i, kGrid / 2)));
    EXPECT_LT(p[2], previous) << "at x = " << q[0];
    EXPECT_NEAR(p[0], q[0], 1e-15);
    EXPECT_NEAR(p[1], q[1], 1e-15);
    // On the ray D(x,H) = x and D(x,L) = 1 - x, so t = x (Eq. 7).
    EXPECT_NEAR(p[2], h * (1 - 3 * q[0] * q[0] + 2 * q[0] * q[0] * q[0]), 1e-12);
    previous = p[2];
  }
  EXPECT_EQ(previous, 0.0);
  EXPECT_EQ(result.report.handles, 1);
  EXPECT_EQ(result.report.maxDisplacement, h);
  // Every interior vertex moves (t < 1), no rim vertex does.
  EXPECT_EQ(result.report.verticesMoved, (kGrid - 2) * (kGrid - 2));
}

TEST(HandleEdit, TheLinearProfileRaisesTheRayByHTimesOneMinusT) {
  const double h = 0.25;
  const auto result = editGrid({translation({0, 0, 0}, 0, {0, 0, h})}, HandleProfile::Linear);
  for (int i = kGrid / 2; i < kGrid; ++i) {
    const auto p = result.mesh.point(TriMesh::VertexHandle(gridVertex(i, kGrid / 2)));
    EXPECT_NEAR(p[2], h * (1 - p[0]), 1e-12) << "at x = " << p[0];
  }
  const auto cosine = editGrid({translation({0, 0, 0}, 0, {0, 0, h})}, HandleProfile::Cosine);
  for (int i = kGrid / 2; i < kGrid; ++i) {
    const auto p = cosine.mesh.point(TriMesh::VertexHandle(gridVertex(i, kGrid / 2)));
    EXPECT_NEAR(p[2], h * (1 + std::cos(std::numbers::pi * p[0])) / 2, 1e-12) << "at x = " << p[0];
  }
}

TEST(HandleEdit, TheHandleMovesExactlyByTAndRigidly) {
  const TriMesh flat = grid(kGrid);
  HandleEdit edit = translation({0.21, -0.12, 0}, 0.16, {0.05, 0, 0.2});
  edit.axis = {1, 1, 0};
  edit.angleDegrees = 25;
  const auto result = editGrid({edit});
  const KnnGraph graph = vertexGraph(flat, 8);
  const HandleRegion region =
      handleRegion(flat, graph, boundaryDistances(flat, graph), edit.point, edit.radius);
  ASSERT_GT(region.vertices.size(), 20u);
  EXPECT_FALSE(region.touchesBoundary);
  const RigidMotion t = handleMotion(edit, pointOf(flat, region.seed));
  for (int v : region.vertices) {
    EXPECT_LE((pointOf(result.mesh, v) - t(pointOf(flat, v))).norm(), 1e-12) << "vertex " << v;
  }
  // alpha = 1 on H: a rigid map, so distances within H are kept.
  for (int a : region.vertices)
    for (int b : region.vertices) {
      EXPECT_NEAR((pointOf(result.mesh, a) - pointOf(result.mesh, b)).norm(),
                  (pointOf(flat, a) - pointOf(flat, b)).norm(), 1e-12);
    }
  expectBoundaryBitIdentical(flat, result.mesh);
}

TEST(HandleEdit, TwoRowsComposeInOrder) {
  const TriMesh flat = grid(kGrid);
  // Translations add up: each row's alpha comes from the unedited template.
  const HandleEdit a = translation({-0.3, 0, 0}, 0.1, {0, 0, 0.2});
  const HandleEdit b = translation({0.3, 0.1, 0}, 0, {0.1, 0, -0.1});
  const auto onlyA = editGrid({a});
  const auto onlyB = editGrid({b});
  const auto both = editGrid({a, b});
  for (int v = 0; v < int(flat.n_vertices()); ++v) {
    const Eigen::Vector3d sum =
        pointOf(onlyA.mesh, v) - pointOf(flat, v) + pointOf(onlyB.mesh, v) - pointOf(flat, v);
    EXPECT_LE((pointOf(both.mesh, v) - pointOf(flat, v) - sum).norm(), 1e-12) << "vertex " << v;
  }
  EXPECT_EQ(both.report.handles, 2);

  // With a turn first, the second row acts on the turned points about its seed as turned.
  HandleEdit turn = translation({0, 0, 0}, 0.4, {0, 0, 0});
  turn.axis = {1, 0, 0};
  turn.angleDegrees = 20;
  const HandleEdit lift = translation({0.1, 0, 0}, 0.05, {0, 0, 0.3});
  const auto turned = editGrid({turn});
  const auto turnedThenLifted = editGrid({turn, lift});
  const auto liftedThenTurned = editGrid({lift, turn});
  const KnnGraph graph = vertexGraph(flat, 8);
  const HandleRegion liftRegion =
      handleRegion(flat, graph, boundaryDistances(flat, graph), lift.point, lift.radius);
  const RigidMotion t = handleMotion(lift, pointOf(turned.mesh, liftRegion.seed));
  for (int v : liftRegion.vertices) {
    EXPECT_LE((pointOf(turnedThenLifted.mesh, v) - t(pointOf(turned.mesh, v))).norm(), 1e-12);
  }
  double difference = 0;
  for (int v = 0; v < int(flat.n_vertices()); ++v)
    difference = std::max(
        difference, (pointOf(turnedThenLifted.mesh, v) - pointOf(liftedThenTurned.mesh, v)).norm());
  EXPECT_GT(difference, 1e-3);
}

TEST(HandleEdit, RefusesATemplateWithoutBoundaryAndAHandleOnIt) {
  HandleEditOptions options;
  options.edits = {translation({1, 0, 0}, 0, {0, 0, 1})};
  try {
    editTemplate(test::icosphere(2), options);
    ADD_FAILURE() << "a closed template was accepted";
  } catch (const HandleEditError& e) {
    EXPECT_EQ(e.option(), "template");
    EXPECT_TRUE(test::contains(e.what(), "no boundary"));
  }
  options.edits = {translation({0, 0, 0}, 0, {0, 0, 1}),
                   translation({0.5, 0, 0}, 0.6, {0, 0, 1})};  // reaches the rim at x = 1
  try {
    editTemplate(grid(kGrid), options);
    ADD_FAILURE() << "a handle on the boundary was accepted";
  } catch (const HandleEditError& e) {
    EXPECT_EQ(e.option(), "edits");
    EXPECT_TRUE(test::contains(e.what(), "row 2: the handle touches the template's boundary"));
  }
}

TEST(HandleEdit, EditsARealPatchKeepingItsBoundary) {
  const TriMesh patch = readMesh("cases/nefertiti_back_removed_patch.obj");
  ASSERT_GT(patch.n_vertices(), 400u);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v = 0; v < int(patch.n_vertices()); ++v)
    centroid += pointOf(patch, v);
  centroid /= double(patch.n_vertices());
  const double diagonal = boundingDiagonal(patch);
  HandleEdit edit = translation(centroid, 2 * meanEdgeLength(patch), {0, 0.05 * diagonal, 0});
  edit.axis = {0.3, 0.2, 1};
  edit.angleDegrees = 12;
  HandleEditOptions options;
  options.edits = {edit};
  const auto result = editTemplate(patch, options);
  expectBoundaryBitIdentical(patch, result.mesh);
  EXPECT_EQ(test::faceIndices(patch), test::faceIndices(result.mesh));

  const KnnGraph graph = vertexGraph(patch, 8);
  const HandleRegion region =
      handleRegion(patch, graph, boundaryDistances(patch, graph), edit.point, edit.radius);
  ASSERT_GT(region.vertices.size(), 3u);
  const RigidMotion t = handleMotion(edit, pointOf(patch, region.seed));
  for (int v : region.vertices) {
    EXPECT_LE((pointOf(result.mesh, v) - t(pointOf(patch, v))).norm(), 1e-12 * diagonal);
  }
  EXPECT_GT(result.report.verticesMoved, int(region.vertices.size()));
  EXPECT_GE(result.report.maxDisplacement, 0.05 * diagonal * (1 - 1e-12));
  EXPECT_TRUE(test::bitIdentical(result.mesh, editTemplate(patch, options).mesh));
}

// U4 for a non-rigid handle: two vertices of the grid moved by different translations. Each
// lands exactly at its own translation, the rim keeps its bits, and the vertex halfway between
// the two moves by a blend of both.
TEST(HandleEdit, ANonrigidHandleMovesEachVertexByItsOwnTranslation) {
  const TriMesh flat = grid(kGrid);
  HandleEditOptions options;
  // The grid's vertices at x = -0.3 and 0.3 on the middle row.
  const int va = gridVertex(14, kGrid / 2), vb = gridVertex(26, kGrid / 2);
  const Eigen::Vector3d a = pointOf(flat, va), b = pointOf(flat, vb);
  options.nonrigid = {{a, {0, 0, 0.2}}, {b, {0.05, 0, 0.1}}};
  const auto result = editTemplate(flat, options);
  EXPECT_EQ(pointOf(result.mesh, va), a + Eigen::Vector3d(0, 0, 0.2));
  EXPECT_EQ(pointOf(result.mesh, vb), b + Eigen::Vector3d(0.05, 0, 0.1));
  expectBoundaryBitIdentical(flat, result.mesh);
  EXPECT_EQ(result.report.handles, 1);
  const Eigen::Vector3d middle = pointOf(result.mesh, gridVertex(kGrid / 2, kGrid / 2));
  EXPECT_GT(middle.z(), 0.1 * 0.5);
  EXPECT_LT(middle.z(), 0.2);
  EXPECT_GT(middle.x(), 0);
  EXPECT_LT(middle.x(), 0.05);
  EXPECT_TRUE(test::bitIdentical(result.mesh, editTemplate(flat, options).mesh));
}

TEST(HandleEdit, ANonrigidHandleRefusesAVertexOnTheBoundaryOrTwiceTheSame) {
  const TriMesh flat = grid(kGrid);
  const KnnGraph graph = vertexGraph(flat, 8);
  const BoundaryDistances boundary = boundaryDistances(flat, graph);
  const auto refusal = [&](const std::vector<HandleVertexMove>& moves) {
    try {
      nonrigidHandleField(flat, graph, boundary, moves, HandleProfile::Smoothstep);
    } catch (const HandleEditError& e) {
      EXPECT_EQ(e.option(), "nonrigid_handle");
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_TRUE(test::contains(refusal({{{1, 0, 0}, {0, 0, 1}}}), "row 1: the vertex is on"));
  EXPECT_TRUE(test::contains(refusal({{{0, 0, 0}, {0, 0, 1}}, {{0.001, 0, 0}, {0, 0, 2}}}),
                             "row 2: an earlier row moves the same vertex"));
  EXPECT_EQ(refusal({{{0, 0, 0}, {0, 0, 1}}}), "(accepted)");
  try {
    movesFromRows(std::vector<double>{0, 0, 0, 1, 2});
    ADD_FAILURE() << "five numbers accepted";
  } catch (const HandleEditError& e) {
    EXPECT_EQ(e.option(), "nonrigid_handle");
  }
}

// On a real patch: three vertices far from its boundary and apart from each other, pushed along
// different directions, keep their translations exactly and the patch's boundary stays.
TEST(HandleEdit, ANonrigidHandleShapesARealPatchKeepingItsBoundary) {
  const TriMesh patch = readMesh("cases/nefertiti_back_removed_patch.obj");
  const double diagonal = boundingDiagonal(patch);
  const KnnGraph graph = vertexGraph(patch, 8);
  const BoundaryDistances boundary = boundaryDistances(patch, graph);
  // From the farthest from the boundary on, vertices a tenth of the diagonal from those taken.
  std::vector<int> byDepth(patch.n_vertices());
  std::iota(byDepth.begin(), byDepth.end(), 0);
  std::sort(byDepth.begin(), byDepth.end(), [&](int u, int v) {
    return boundary.toBoundary[std::size_t(u)] > boundary.toBoundary[std::size_t(v)];
  });
  std::vector<int> order;
  for (int v : byDepth) {
    bool apart = true;
    for (int u : order)
      apart = apart && (pointOf(patch, u) - pointOf(patch, v)).norm() > 0.1 * diagonal;
    if (apart) order.push_back(v);
    if (order.size() == 3) break;
  }
  ASSERT_EQ(order.size(), 3u);
  HandleEditOptions options;
  const std::vector<Eigen::Vector3d> pushes = {
      {0.04 * diagonal, 0, 0}, {0, 0.04 * diagonal, 0}, {0, 0, 0.04 * diagonal}};
  for (int i = 0; i < 3; ++i)
    options.nonrigid.push_back({pointOf(patch, order[std::size_t(i)]), pushes[std::size_t(i)]});
  const auto result = editTemplate(patch, options);
  expectBoundaryBitIdentical(patch, result.mesh);
  for (int i = 0; i < 3; ++i) {
    const int v = order[std::size_t(i)];
    EXPECT_EQ(pointOf(result.mesh, v), pointOf(patch, v) + pushes[std::size_t(i)]);
  }
  EXPECT_GT(result.report.verticesMoved, 3);
}

// The node on a plane primitive: `edits` rows as the studio writes them.
Graph planeGraph(const std::vector<double>& edits, std::int64_t resolution = 40) {
  Graph graph;
  graph.nodes["plane"] = {
      "geobrush.primitive",
      1,
      {{"shape", std::string("plane")}, {"size", 2.0}, {"resolution", resolution}}};
  graph.nodes["edit"] = {"geobrush.handle_edit", 1, {{"edits", edits}}};
  graph.connections.push_back({{"plane", "mesh"}, {"edit", "template"}});
  prepareGraph(graph, test::registry());
  return graph;
}

std::shared_ptr<const Mesh> editedOutput(const Evaluator& evaluator) {
  return std::dynamic_pointer_cast<const Mesh>(evaluator.output("edit", "template"));
}

TEST(HandleEditNode, ADragOfTheLastRowReusesEveryDerivedEntryAndEqualsAFreshEvaluation) {
  std::vector<double> rows = {-0.3, 0.2, 0, 0.1, 0, 0, 0.2, 0, 0, 1, 15,
                              0.3,  0,   0, 0,   0, 0, 0.1, 0, 0, 0, 0};
  Evaluator evaluator(test::registry());
  ASSERT_TRUE(evaluator.evaluate(planeGraph(rows)).ok);
  ASSERT_NE(editedOutput(evaluator), nullptr);
  const std::uint64_t builds = evaluator.derivedBuildCount();
  // Enough drags that the node reuses the memory of results nothing holds any more; one result
  // kept here must stay as it was.
  std::shared_ptr<const Mesh> kept;
  TriMesh keptCopy;
  std::set<const Mesh*> results;
  for (double z : {0.15, 0.3, -0.2, 0.05, 0.25, -0.1}) {
    rows[11 + 6] = z;
    rows[11 + 4] = z / 3;
    const Graph dragged = planeGraph(rows);
    const EvalReport report = evaluator.evaluate(dragged);
    ASSERT_TRUE(report.ok) << report.error;
    EXPECT_EQ(evaluator.derivedBuildCount(), builds);
    Evaluator fresh(test::registry());
    ASSERT_TRUE(fresh.evaluate(dragged).ok);
    EXPECT_TRUE(test::bitIdentical(editedOutput(evaluator)->surface, editedOutput(fresh)->surface));
    results.insert(editedOutput(evaluator).get());
    if (!kept) {
      kept = editedOutput(evaluator);
      keptCopy = kept->surface;
    }
  }
  EXPECT_TRUE(test::bitIdentical(kept->surface, keptCopy));
  EXPECT_LT(results.size(), 6u);  // results retired were recycled
  // Another template (other connectivity) after the drags: again a fresh evaluation's result.
  for (std::int64_t resolution : {30, 40}) {
    const Graph other = planeGraph(rows, resolution);
    ASSERT_TRUE(evaluator.evaluate(other).ok);
    Evaluator fresh(test::registry());
    ASSERT_TRUE(fresh.evaluate(other).ok);
    EXPECT_TRUE(test::bitIdentical(editedOutput(evaluator)->surface, editedOutput(fresh)->surface));
  }
  // The node computes what the algorithm does.
  HandleEditOptions options;
  options.edits = editsFromRows(rows);
  const auto plane = std::dynamic_pointer_cast<const Mesh>(evaluator.output("plane", "mesh"));
  const HandleEditResult direct = editTemplate(plane->surface, options);
  EXPECT_TRUE(test::bitIdentical(editedOutput(evaluator)->surface, direct.mesh));
  const auto report = std::dynamic_pointer_cast<const Metrics>(evaluator.output("edit", "report"));
  ASSERT_NE(report, nullptr);
  EXPECT_EQ(report->values.at("handles"), 2);
  EXPECT_GT(report->values.at("vertices_moved"), 0);
  EXPECT_EQ(report->values.at("vertices_moved"), direct.report.verticesMoved);
  EXPECT_EQ(report->values.at("max_displacement"), direct.report.maxDisplacement);
}

// The NodeError a run of the node throws, or a failure.
NodeError nodeError(const std::shared_ptr<const Mesh>& mesh, const ParamMap& params) {
  try {
    test::runNode("geobrush.handle_edit", {{"template", mesh}}, params);
  } catch (const NodeError& e) {
    return e;
  }
  ADD_FAILURE() << "the node accepted bad input";
  return NodeError("");
}

TEST(HandleEditNode, NamesThePortOrParamOfEachBadInput) {
  const auto closed = std::make_shared<const Mesh>(test::icosphere(2));
  const std::vector<double> centre = {0, 0, 0, 0, 0, 0, 0.1, 0, 0, 1, 0};
  EXPECT_EQ(nodeError(closed, {{"edits", centre}}).where(), "input 'template'");

  const auto plane = std::make_shared<const Mesh>(grid(kGrid));
  std::vector<double> onRim = centre;
  onRim.insert(onRim.end(), {1, 0.3, 0, 0, 0, 0, 0.1, 0, 0, 1, 0});
  const NodeError rim = nodeError(plane, {{"edits", onRim}});
  EXPECT_EQ(rim.where(), "param 'edits'");
  EXPECT_TRUE(test::contains(rim.what(), "row 2"));

  std::vector<double> notFinite = centre;
  notFinite[4] = INFINITY;
  const NodeError bad = nodeError(plane, {{"edits", notFinite}});
  EXPECT_EQ(bad.where(), "param 'edits'");
  EXPECT_TRUE(test::contains(bad.what(), "row 1"));
  EXPECT_EQ(nodeError(plane, {{"edits", std::vector<double>(12, 0.0)}}).where(), "param 'edits'");
  EXPECT_EQ(nodeError(plane, {{"edits", centre}, {"profile", std::string("cubic")}}).where(),
            "param 'profile'");
  EXPECT_EQ(nodeError(plane, {{"edits", centre}, {"profile", std::string("custom")}}).where(),
            "param 'profile_samples'");
  const NodeError moveOnRim =
      nodeError(plane, {{"nonrigid_handle", std::vector<double>{1, 0, 0, 0, 0, 0.1}}});
  EXPECT_EQ(moveOnRim.where(), "param 'nonrigid_handle'");
  EXPECT_TRUE(test::contains(moveOnRim.what(), "row 1"));
  // A non-rigid handle through the node: its vertex moved exactly, reported.
  const auto moved = test::runNode("geobrush.handle_edit", {{"template", plane}},
                                   {{"nonrigid_handle", std::vector<double>{0, 0, 0, 0, 0, 0.1}}});
  const int centreVertex = gridVertex(kGrid / 2, kGrid / 2);
  EXPECT_EQ(pointOf(moved.get<Mesh>("template")->surface, centreVertex),
            Eigen::Vector3d(0, 0, 0.1));
  EXPECT_EQ(moved.get<Metrics>("report")->values.at("nonrigid_vertices"), 1);

  // No edits: the template passes unchanged.
  const auto run = test::runNode("geobrush.handle_edit", {{"template", plane}});
  ASSERT_NE(run.get<Mesh>("template"), nullptr);
  EXPECT_TRUE(test::bitIdentical(run.get<Mesh>("template")->surface, plane->surface));
  EXPECT_EQ(run.get<Metrics>("report")->values.at("vertices_moved"), 0);
}

}  // namespace
}  // namespace geobrush
