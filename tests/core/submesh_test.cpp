// extractSubmesh and appendFaces: faces copied with their vertices renumbered in source order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "geobrush/mesh_io.hpp"
#include "geobrush/submesh.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

using namespace geobrush;

TEST(Submesh, CopiesFacesAndRenumbersVertices) {
  const Mesh tet = test::tetrahedron({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});
  // Faces 3 then 1: (1, 2, 3) and (0, 1, 3).
  const Submesh sub = extractSubmesh(tet.surface, {3, 1});
  EXPECT_EQ(sub.unattachedFace, -1);
  EXPECT_EQ(sub.sourceVertex, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(sub.sourceFace, (std::vector<int>{3, 1}));
  ASSERT_EQ(sub.surface.n_faces(), 2u);
  for (int f = 0; f < 2; ++f) {
    auto a = sub.surface.cfv_begin(TriMesh::FaceHandle(f));
    auto b = tet.surface.cfv_begin(TriMesh::FaceHandle(sub.sourceFace[f]));
    for (int k = 0; k < 3; ++k, ++a, ++b)
      EXPECT_EQ(sub.sourceVertex[a->idx()], b->idx());
  }
  const Submesh one = extractSubmesh(tet.surface, {2});
  EXPECT_EQ(one.sourceVertex, (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(one.surface.point(TriMesh::VertexHandle(1)),
            tet.surface.point(TriMesh::VertexHandle(2)));
}

namespace {

// Every halfedge's links agree with each other and OpenMesh's boundary queries hold: what add_face
// would have made.
void expectConsistentConnectivity(const TriMesh& mesh) {
  for (auto h : mesh.halfedges()) {
    const auto next = mesh.next_halfedge_handle(h);
    ASSERT_TRUE(next.is_valid());
    EXPECT_EQ(mesh.prev_halfedge_handle(next), h);
    EXPECT_EQ(mesh.from_vertex_handle(next), mesh.to_vertex_handle(h));
    EXPECT_EQ(mesh.face_handle(next), mesh.face_handle(h));
    EXPECT_NE(mesh.to_vertex_handle(h), mesh.from_vertex_handle(h));
  }
  for (auto f : mesh.faces())
    EXPECT_EQ(mesh.face_handle(mesh.halfedge_handle(f)), f);
  for (auto v : mesh.vertices()) {
    EXPECT_EQ(mesh.from_vertex_handle(mesh.halfedge_handle(v)), v);
    bool anyBoundary = false;
    for (auto h : mesh.voh_range(v))
      anyBoundary = anyBoundary || mesh.is_boundary(h);
    EXPECT_EQ(mesh.is_boundary(v), anyBoundary) << "vertex " << v.idx();
  }
}

// The faces of an icosphere below a wavy cut: a disc with a jagged boundary.
std::vector<int> facesBelowWavyCut(const TriMesh& sphere) {
  std::vector<int> faces;
  for (auto f : sphere.faces()) {
    const auto c = sphere.calc_face_centroid(f);
    if (c[2] < 0.3 + 0.2 * std::sin(7 * std::atan2(c[1], c[0]))) faces.push_back(f.idx());
  }
  return faces;
}

// The faces below the wavy cut, and the others.
std::pair<std::vector<int>, std::vector<int>> splitAtWavyCut(const TriMesh& sphere) {
  std::vector<int> below = facesBelowWavyCut(sphere), above;
  std::vector<char> isBelow(sphere.n_faces(), 0);
  for (int f : below)
    isBelow[std::size_t(f)] = 1;
  for (std::size_t f = 0; f < sphere.n_faces(); ++f)
    if (!isBelow[f]) above.push_back(int(f));
  return {below, above};
}

}  // namespace

namespace {

// extractSubmesh as add_face builds it, face by face: the reference for its direct linking.
TriMesh addedFaceByFace(const TriMesh& mesh, const std::vector<int>& faces,
                        const std::vector<int>& sourceVertex) {
  TriMesh out;
  std::vector<int> local(mesh.n_vertices(), -1);
  for (std::size_t i = 0; i < sourceVertex.size(); ++i) {
    local[std::size_t(sourceVertex[i])] = int(i);
    out.add_vertex(mesh.point(TriMesh::VertexHandle(sourceVertex[i])));
  }
  for (int f : faces) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      corners.push_back(TriMesh::VertexHandle(local[std::size_t(v.idx())]));
    EXPECT_TRUE(out.add_face(corners).is_valid());
  }
  return out;
}

void expectLinkedAsAddFaceDoes(const TriMesh& mesh, const std::vector<int>& faces) {
  const Submesh sub = extractSubmesh(mesh, faces);
  ASSERT_EQ(sub.unattachedFace, -1);
  EXPECT_EQ(sub.sourceFace, faces);
  EXPECT_TRUE(std::is_sorted(sub.sourceVertex.begin(), sub.sourceVertex.end()));
  EXPECT_TRUE(
      test::sameHalfedgeStructure(sub.surface, addedFaceByFace(mesh, faces, sub.sourceVertex)));
  expectConsistentConnectivity(sub.surface);
}

}  // namespace

// The submesh is linked directly (several times faster than add_face on a canvas of tens of
// thousands of faces), to the very halfedges add_face would make, in any face order: a disc with
// a jagged edge, an annulus, a closed sphere, shuffled faces, a real scan with its own holes.
TEST(Submesh, LinksFacesAsAddFaceDoes) {
  const TriMesh sphere = test::icosphere(3);
  const std::vector<int> disc = facesBelowWavyCut(sphere);
  expectLinkedAsAddFaceDoes(sphere, disc);
  std::vector<int> annulus;
  for (int f : disc) {
    const auto c = sphere.calc_face_centroid(TriMesh::FaceHandle(f));
    if (c[2] > -0.6) annulus.push_back(f);
  }
  expectLinkedAsAddFaceDoes(sphere, annulus);
  std::vector<int> all(sphere.n_faces());
  std::iota(all.begin(), all.end(), 0);
  expectLinkedAsAddFaceDoes(sphere, all);
  // Reversed, and every seventh first: faces that meet only later, fans grown from both sides.
  std::vector<int> shuffled(disc.rbegin(), disc.rend());
  std::stable_partition(shuffled.begin(), shuffled.end(), [](int f) { return f % 7 == 0; });
  expectLinkedAsAddFaceDoes(sphere, shuffled);

  // A ball of a real scan around one of its vertices, a tenth of its size across.
  const MeshPtr bunny = readMesh(test::meshPath("bunny_scan.obj")).mesh;
  ASSERT_TRUE(bunny);
  const TriMesh& scan = bunny->surface;
  OpenMesh::Vec3d lo = scan.point(TriMesh::VertexHandle(0)), hi = lo;
  for (auto v : scan.vertices()) {
    lo.minimize(scan.point(v));
    hi.maximize(scan.point(v));
  }
  const auto centre = scan.point(TriMesh::VertexHandle(int(scan.n_vertices() / 3)));
  std::vector<int> ball;
  for (auto f : scan.faces())
    if ((scan.calc_face_centroid(f) - centre).norm() < 0.05 * (hi - lo).norm())
      ball.push_back(f.idx());
  ASSERT_GT(ball.size(), 500u);
  expectLinkedAsAddFaceDoes(scan, ball);
}

// Where the faces meet at a vertex in two fans, add_face links them as it can.
TEST(Submesh, TwoFansAtAVertexAreLinkedByAddFace) {
  const TriMesh sphere = test::icosphere(2);
  const auto v = TriMesh::VertexHandle(0);
  std::vector<int> fan;
  for (auto f : sphere.vf_range(v))
    fan.push_back(f.idx());
  ASSERT_GE(fan.size(), 5u);
  // Two faces around the vertex, not adjacent: a bow tie.
  const std::vector<int> bowTie = {fan[0], fan[2]};
  const Submesh sub = extractSubmesh(sphere, bowTie);
  ASSERT_EQ(sub.unattachedFace, -1);
  EXPECT_EQ(sub.surface.n_faces(), 2u);
  EXPECT_TRUE(
      test::sameHalfedgeStructure(sub.surface, addedFaceByFace(sphere, bowTie, sub.sourceVertex)));
}

TEST(AppendFaces, CopiesWhatExtractSubmeshBuildsFaceByFace) {
  const TriMesh sphere = test::icosphere(3);
  const std::vector<int> faces = facesBelowWavyCut(sphere);
  const Submesh reference = extractSubmesh(sphere, faces);
  ASSERT_EQ(reference.unattachedFace, -1);
  TriMesh copy;
  const AppendedFaces added = appendFaces(copy, sphere, faces);
  EXPECT_EQ(added.firstVertex, 0);
  EXPECT_EQ(added.sourceVertex, reference.sourceVertex);
  EXPECT_TRUE(test::bitIdentical(copy, reference.surface));
  expectConsistentConnectivity(copy);
  const test::Topology expected = test::topology(reference.surface);
  const test::Topology got = test::topology(copy);
  EXPECT_EQ(got.edges, expected.edges);
  EXPECT_EQ(got.boundaryHalfedges, expected.boundaryHalfedges);
  EXPECT_EQ(got.boundaryLoops, 1u);
  EXPECT_EQ(got.nonManifoldVertices, 0u);
  for (std::size_t v = 0; v < sphere.n_vertices(); ++v) {
    const auto it = std::lower_bound(added.sourceVertex.begin(), added.sourceVertex.end(), int(v));
    const bool isUsed = it != added.sourceVertex.end() && *it == int(v);
    EXPECT_EQ(added.vertexInOut[v], isUsed ? int(it - added.sourceVertex.begin()) : -1);
  }
}

// A few faces of a large mesh (a small cap: their edges and vertices are marked from the faces,
// not by a walk over the mesh) are copied as exactly.
TEST(AppendFaces, CopiesAFewFacesAsExactly) {
  const TriMesh sphere = test::icosphere(4);
  std::vector<int> cap;
  for (auto f : sphere.faces()) {
    bool near = true;
    for (auto v : sphere.fv_range(f))
      near = near && sphere.point(v)[2] > 0.9;
    if (near) cap.push_back(f.idx());
  }
  ASSERT_GT(cap.size(), 20u);
  ASSERT_LT(cap.size() * 8, sphere.n_faces());
  const Submesh reference = extractSubmesh(sphere, cap);
  ASSERT_EQ(reference.unattachedFace, -1);
  TriMesh copy;
  const AppendedFaces added = appendFaces(copy, sphere, cap);
  EXPECT_EQ(added.sourceVertex, reference.sourceVertex);
  EXPECT_TRUE(test::bitIdentical(copy, reference.surface));
  expectConsistentConnectivity(copy);
  EXPECT_EQ(test::topology(copy).boundaryLoops, 1u);
}

TEST(AppendFaces, AppendsAfterWhatIsThereAndKeepsTheMeshOpenToAddFace) {
  const TriMesh sphere = test::icosphere(2);
  const auto [below, above] = splitAtWavyCut(sphere);
  TriMesh both;
  appendFaces(both, sphere, below);
  const std::size_t verticesBelow = both.n_vertices();
  const AppendedFaces second = appendFaces(both, sphere, above);
  EXPECT_EQ(second.firstVertex, int(verticesBelow));
  expectConsistentConnectivity(both);
  const test::Topology parts = test::topology(both);
  EXPECT_EQ(parts.components, 2u);
  EXPECT_EQ(parts.boundaryLoops, 2u);
  EXPECT_EQ(parts.faces, sphere.n_faces());

  // The copy of the cap takes new faces at its boundary like any OpenMesh mesh: close its hole
  // with a fan around a new centre vertex.
  TriMesh cap;
  appendFaces(cap, sphere, below);
  std::vector<TriMesh::HalfedgeHandle> rim;
  for (auto h : cap.halfedges())
    if (cap.is_boundary(h)) rim.push_back(h);
  const auto centre = cap.add_vertex({0, 0, 1});
  for (auto h : rim)
    ASSERT_TRUE(
        cap.add_face(cap.from_vertex_handle(h), cap.to_vertex_handle(h), centre).is_valid());
  expectConsistentConnectivity(cap);
  const test::Topology closed = test::topology(cap);
  EXPECT_EQ(closed.boundaryLoops, 0u);
  EXPECT_EQ(closed.eulerCharacteristic, 2);
}

namespace {

// The faces around vertex 0, in circulation order.
std::vector<int> facesAroundVertexZero(const TriMesh& mesh) {
  std::vector<int> fan;
  for (auto f : mesh.vf_range(TriMesh::VertexHandle(0)))
    fan.push_back(f.idx());
  return fan;
}

// The faces a circulator meets going round `v`.
int facesRound(const TriMesh& mesh, TriMesh::VertexHandle v) {
  int faces = 0;
  for (auto f : mesh.vf_range(v))
    faces += f.is_valid();
  return faces;
}

}  // namespace

TEST(AppendFaces, GivesAPinchedSelectionAVertexThatCirculatorsGoRoundWhole) {
  // Two opposite faces around one vertex of an icosphere share only that vertex.
  const TriMesh sphere = test::icosphere(1);
  const std::vector<int> fan = facesAroundVertexZero(sphere);
  ASSERT_EQ(fan.size(), 5u);
  TriMesh pinched;
  const AppendedFaces added = appendFaces(pinched, sphere, {fan[0], fan[2]});
  expectConsistentConnectivity(pinched);
  const test::Topology t = test::topology(pinched);
  EXPECT_EQ(t.nonManifoldVertices, 1u);
  EXPECT_EQ(t.faces, 2u);
  EXPECT_EQ(facesRound(pinched, TriMesh::VertexHandle(added.vertexInOut[0])), 2);
}

// Faces joined to nothing around one vertex of an icosphere: the whole fan (the vertex inside the
// copy), part of it (on the boundary) and two faces that share only the vertex (a pinch): each
// vertex holds a boundary halfedge where it has one, and circulators go round every fan.
TEST(JoinFaces, GivesNewVerticesABoundaryHalfedgeWhereTheyHaveOne) {
  const TriMesh sphere = test::icosphere(1);
  const std::vector<int> fan = facesAroundVertexZero(sphere);
  ASSERT_EQ(fan.size(), 5u);
  AppendedFaces nothing;
  nothing.vertexInOut.assign(sphere.n_vertices(), -1);
  nothing.edgeInOut.assign(sphere.n_edges(), -1);
  nothing.faceInOut.assign(sphere.n_faces(), -1);
  const std::vector<std::vector<int>> selections = {
      fan, {fan[0], fan[1], fan[2]}, {fan[0], fan[2]}};
  for (std::size_t k = 0; k < selections.size(); ++k) {
    SCOPED_TRACE(k);
    TriMesh joined;
    const AppendedFaces added = joinFaces(joined, sphere, selections[k], nothing);
    expectConsistentConnectivity(joined);
    const auto centre = TriMesh::VertexHandle(added.vertexInOut[0]);
    EXPECT_EQ(joined.is_boundary(centre), k > 0);
    EXPECT_EQ(facesRound(joined, centre), int(selections[k].size()));
    EXPECT_EQ(test::topology(joined).nonManifoldVertices, k == 2 ? 1u : 0u);
  }
}

// A cap copied first and the rest of the sphere joined to it close into the whole sphere; joining
// a ring of faces leaves two boundary loops where the parts meet nothing.
TEST(JoinFaces, ClosesTheBoundaryBetweenTheCopiedParts) {
  const TriMesh sphere = test::icosphere(3);
  const auto [below, above] = splitAtWavyCut(sphere);
  TriMesh whole;
  const AppendedFaces cap = appendFaces(whole, sphere, below);
  const AppendedFaces all = joinFaces(whole, sphere, above, cap);
  expectConsistentConnectivity(whole);
  const test::Topology t = test::topology(whole);
  EXPECT_EQ(t.vertices, sphere.n_vertices());
  EXPECT_EQ(t.faces, sphere.n_faces());
  EXPECT_EQ(t.edges, sphere.n_edges());
  EXPECT_EQ(t.boundaryLoops, 0u);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.eulerCharacteristic, 2);
  // Every face has its source face's corners.
  for (std::size_t f = 0; f < sphere.n_faces(); ++f) {
    auto a = whole.cfv_begin(TriMesh::FaceHandle(all.faceInOut[f]));
    auto b = sphere.cfv_begin(TriMesh::FaceHandle(int(f)));
    for (int k = 0; k < 3; ++k, ++a, ++b)
      EXPECT_EQ(a->idx(), all.vertexInOut[std::size_t(b->idx())]);
  }
  for (auto v : whole.vertices())
    EXPECT_FALSE(whole.is_boundary(v));

  // Only the faces touching the cut: a band with boundary on both sides.
  std::vector<int> band;
  for (int f : above) {
    bool touchesCap = false;
    for (auto v : sphere.fv_range(TriMesh::FaceHandle(f)))
      touchesCap = touchesCap || cap.vertexInOut[std::size_t(v.idx())] >= 0;
    if (touchesCap) band.push_back(f);
  }
  TriMesh capAndBand;
  const AppendedFaces first = appendFaces(capAndBand, sphere, below);
  joinFaces(capAndBand, sphere, band, first);
  expectConsistentConnectivity(capAndBand);
  const test::Topology b = test::topology(capAndBand);
  EXPECT_EQ(b.components, 1u);
  EXPECT_EQ(b.faces, below.size() + band.size());
  std::vector<int> capAndBandFaces = below;
  capAndBandFaces.insert(capAndBandFaces.end(), band.begin(), band.end());
  EXPECT_EQ(b.boundaryLoops,
            test::topology(extractSubmesh(sphere, capAndBandFaces).surface).boundaryLoops);
  EXPECT_EQ(b.nonManifoldVertices, 0u);
}
