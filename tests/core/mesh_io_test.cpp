// Mesh files: reading with its checks and repairs, writing, round trips, statistics, and the
// mesh value's hash and summary.
#include <gtest/gtest.h>

#include <OpenMesh/Core/System/omstream.hh>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <thread>

#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

using namespace geobrush;
using OpenMesh::Vec3d;

namespace {

namespace fs = std::filesystem;
using test::writeFile;

// The file name as messages quote it.
std::string quoted(const fs::path& path) {
  std::string text = "'";
  text += path.string();
  text += '\'';
  return text;
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' lacks '" << part << "'";
}

// The message of the MeshError that reading `path` throws, or "" if it reads.
std::string readError(const fs::path& path, const MeshReadOptions& options = {}) {
  try {
    readMesh(path, options);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::array<int, 3>> faces(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> result;
  for (auto face : mesh.faces()) {
    std::array<int, 3> corners{};
    int k = 0;
    for (auto vertex : mesh.fv_range(face))
      corners[k++] = vertex.idx();
    result.push_back(corners);
  }
  return result;
}

Vec3d pointVec(const TriMesh& mesh, int index) {
  return mesh.point(TriMesh::VertexHandle(index));
}

const std::string kTetrahedron =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

// Coordinates that no short decimal and no 32-bit float holds exactly, within the float range.
Mesh awkwardTetrahedron() {
  return test::tetrahedron({Vec3d(1.0 / 3, -0.0, 1e-30), Vec3d(M_PI, 2.0 / 7, -1e30 / 7),
                            Vec3d(0.1, std::nextafter(1.0, 2.0), 123456789.123456789),
                            Vec3d(-1e-40, 0.7, std::sqrt(2.0))});
}

// Beyond the float range too: the extremes of double.
Mesh extremeTetrahedron() {
  return test::tetrahedron(
      {Vec3d(1.0 / 3, -0.0, 1e-300), Vec3d(M_PI, 2.0 / 7, -1e300 / 7),
       Vec3d(0.1, std::nextafter(1.0, 2.0), std::numeric_limits<double>::max()),
       Vec3d(-5e-324, 0.7, std::numeric_limits<double>::min())});
}

// ------------------------------------------------------------------------------------------------
// The shipped meshes, against the counts in their README.

struct ShippedMesh {
  const char* file;
  std::size_t vertices;
  std::size_t faces;
  std::size_t boundaryLoops;
  int genus;
};

class MeshIoShipped : public ::testing::TestWithParam<ShippedMesh> {};

TEST_P(MeshIoShipped, HasTheDocumentedCountsAndTopology) {
  const ShippedMesh& expected = GetParam();
  const MeshReadResult result = readMesh(test::meshPath(expected.file));
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  const MeshStats stats = meshStats(result.mesh->surface);
  EXPECT_EQ(stats.vertices, expected.vertices);
  EXPECT_EQ(stats.faces, expected.faces);
  EXPECT_EQ(stats.boundaryLoops, expected.boundaryLoops);
  EXPECT_EQ(stats.components, 1u);
  EXPECT_EQ(stats.isolatedVertices, 0u);
  EXPECT_EQ(stats.nonFiniteVertices, 0u);
  EXPECT_EQ(stats.eulerCharacteristic,
            2 - 2 * expected.genus - static_cast<int>(expected.boundaryLoops));
}

INSTANTIATE_TEST_SUITE_P(Readme, MeshIoShipped,
                         ::testing::Values(ShippedMesh{"armadillo.obj", 14587, 29170, 0, 0},
                                           ShippedMesh{"boot.obj", 19931, 39906, 0, 12},
                                           ShippedMesh{"bunny_scan.obj", 34834, 69451, 5, 0},
                                           ShippedMesh{"bunny_small.obj", 1839, 3674, 0, 0},
                                           ShippedMesh{"cube.obj", 866, 1728, 0, 0},
                                           ShippedMesh{"fandisk.obj", 6475, 12946, 0, 0},
                                           ShippedMesh{"knot.obj", 3200, 6400, 0, 1},
                                           ShippedMesh{"mech_holes_shark.obj", 5246, 10192, 4, 0},
                                           ShippedMesh{"mountain.obj", 25600, 50562, 1, 0},
                                           ShippedMesh{"nefertiti.obj", 35002, 70000, 0, 0},
                                           ShippedMesh{"sphere.obj", 642, 1280, 0, 0},
                                           ShippedMesh{"torus.obj", 2304, 4608, 0, 1}),
                         [](const auto& info) {
                           std::string name = info.param.file;
                           return name.substr(0, name.find('.'));
                         });

TEST(MeshIo, KeepsTheDecimalValuesOfTheFileExactly) {
  // bunny_small.obj's first vertex line; a float-based reader would change each coordinate.
  const auto mesh = readMesh(test::meshPath("bunny_small.obj")).mesh;
  std::ifstream in(test::meshPath("bunny_small.obj"));
  std::string line;
  while (std::getline(in, line) && line.rfind("v ", 0) != 0) {
  }
  double x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z), 3) << line;
  const Vec3d p = pointVec(mesh->surface, 0);
  EXPECT_EQ(p[0], x);
  EXPECT_EQ(p[1], y);
  EXPECT_EQ(p[2], z);
}

// ------------------------------------------------------------------------------------------------
// Small analytic files.

TEST(MeshIo, ReadsATetrahedronInFileOrder) {
  const auto dir = test::tempDir("mesh-io-tet");
  const auto result = readMesh(writeFile(dir / "tet.obj", kTetrahedron));
  EXPECT_TRUE(result.warnings.empty());
  const TriMesh& mesh = result.mesh->surface;
  ASSERT_EQ(mesh.n_vertices(), 4u);
  EXPECT_EQ(pointVec(mesh, 3), Vec3d(0, 0, 1));
  EXPECT_EQ(faces(mesh),
            (std::vector<std::array<int, 3>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}));
  const MeshStats stats = meshStats(mesh);
  EXPECT_EQ(stats.boundaryLoops, 0u);
  EXPECT_EQ(stats.components, 1u);
  EXPECT_EQ(stats.eulerCharacteristic, 2);
  EXPECT_TRUE(result.mesh->vertexColors.empty());
}

TEST(MeshIo, AcceptsObjIndexFormsAndCommentsAndAnyExtensionCase) {
  const auto dir = test::tempDir("mesh-io-forms");
  // Negative indices count back from the last vertex; texture and normal indices are ignored.
  const auto path =
      writeFile(dir / "forms.OBJ",
                "# comment\r\nv 0 0 0\r\nv 1 0 0 # trailing\r\nv 0 1 0\r\nvn 0 0 1\r\n"
                "f 1/1/1 2//1 3\r\nv +1 1 0\r\nf -3 -1 -2\r\n");
  const auto result = readMesh(path);
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_EQ(faces(result.mesh->surface), (std::vector<std::array<int, 3>>{{0, 1, 2}, {1, 3, 2}}));
}

TEST(MeshIo, TriangulatesAQuadWithAWarning) {
  const auto dir = test::tempDir("mesh-io-quad");
  const auto path = writeFile(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const auto result = readMesh(path);
  EXPECT_EQ(faces(result.mesh->surface), (std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}}));
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0],
            quoted(path) +
                ": triangulated 1 polygon with more than 3 corners into 2 triangles (fans from "
                "each first corner)");
  const MeshStats stats = meshStats(result.mesh->surface);
  EXPECT_EQ(stats.boundaryLoops, 1u);
  EXPECT_EQ(stats.eulerCharacteristic, 1);
}

TEST(MeshIo, RefusesANonFiniteCoordinateNamingTheVertex) {
  const auto dir = test::tempDir("mesh-io-nan");
  const auto obj = writeFile(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(readError(obj), quoted(obj) +
                                ": vertex 1 (0-based, line 2) has a non-finite coordinate: "
                                "'v nan 0 0'");
  const auto inf = writeFile(dir / "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n");
  EXPECT_TRUE(contains(readError(inf), "vertex 2 (0-based, line 3) has a non-finite"));
  // OpenMesh's text readers cannot parse "nan"; the file is still named with the vertex.
  const auto off = writeFile(dir / "nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  EXPECT_TRUE(contains(readError(off), "vertex 1 (0-based, line 4) has a non-finite"));
  const auto ply = writeFile(dir / "nan.ply",
                             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 1\n"
                             "property list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 NaN\n3 0 1 2\n");
  EXPECT_TRUE(contains(readError(ply), quoted(ply) + ": vertex 2 (0-based, line 12)"));
  const auto stla = writeFile(dir / "nan.stl",
                              "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 0\nvertex 0 inf 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_TRUE(contains(readError(stla), "facet 0 (0-based, line 6) has a non-finite"));
}

TEST(MeshIo, RefusesANonFiniteCoordinateInABinaryFile) {
  const auto dir = test::tempDir("mesh-io-nan-binary");
  std::string stl(80, ' ');
  const std::uint32_t triangles = 1;
  stl.append(reinterpret_cast<const char*>(&triangles), 4);
  const std::array<float, 12> record{0, 0, 1, 0, 0, 0, 1, 0, 0, std::nanf(""), 1, 0};
  stl.append(reinterpret_cast<const char*>(record.data()), sizeof record);
  stl.append(2, '\0');
  const auto path = writeFile(dir / "nan.stl", stl);
  EXPECT_EQ(readError(path),
            quoted(path) + ": facet 0 (0-based) has a non-finite coordinate: (nan, 1, 0)");
}

TEST(MeshIo, RefusesAFileWithoutFaces) {
  const auto dir = test::tempDir("mesh-io-empty");
  const auto points = writeFile(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_EQ(readError(points), quoted(points) + ": has 3 vertices but no faces");
  const auto empty = writeFile(dir / "empty.obj", "");
  EXPECT_EQ(readError(empty), quoted(empty) + ": holds no vertices and no faces");
  const auto emptyPly = writeFile(dir / "empty.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                  "property float y\nproperty float z\nend_header\n");
  EXPECT_EQ(readError(emptyPly), quoted(emptyPly) + ": holds no vertices and no faces");
}

TEST(MeshIo, RefusesNonManifoldEdgesUnlessRepaired) {
  const auto dir = test::tempDir("mesh-io-nonmanifold");
  // Three triangles around the edge 1-2: the third cannot be attached.
  const auto path = writeFile(dir / "fin.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                              "f 1 2 3\nf 2 1 4\nf 1 2 5\n");
  EXPECT_EQ(readError(path),
            quoted(path) +
                ": 1 face would make an edge or vertex non-manifold or flip the orientation (the "
                "first is face 2 of the file, 0-based); set repair to split them off onto their "
                "own vertices");

  const auto result = readMesh(path, {.repairNonManifold = true, .progress = {}});
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0],
            quoted(path) +
                ": repaired 1 face that would make an edge or vertex non-manifold or flip the "
                "orientation (the first is face 2 of the file, 0-based): split off onto their own "
                "copies of their vertices, 3 vertices added");
  const TriMesh& mesh = result.mesh->surface;
  ASSERT_EQ(mesh.n_faces(), 3u);
  EXPECT_EQ(mesh.n_vertices(), 8u);
  const auto split = TriMesh::FaceHandle(2);
  EXPECT_TRUE(mesh.status(split).fixed_nonmanifold());
  EXPECT_FALSE(mesh.status(TriMesh::FaceHandle(0)).fixed_nonmanifold());
  EXPECT_EQ(faces(mesh)[2], (std::array<int, 3>{5, 6, 7}));
  EXPECT_EQ(pointVec(mesh, 5), pointVec(mesh, 0));
  EXPECT_EQ(pointVec(mesh, 6), pointVec(mesh, 1));
  EXPECT_EQ(pointVec(mesh, 7), pointVec(mesh, 4));
  EXPECT_EQ(meshStats(mesh).components, 2u);
}

TEST(MeshIo, CountsAFlippedNeighbourAsNonManifold) {
  const auto dir = test::tempDir("mesh-io-flip");
  const auto path = writeFile(dir / "flip.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                              "f 1 2 3\nf 1 2 4\n");
  EXPECT_TRUE(
      contains(readError(path), "1 face would make an edge or vertex non-manifold or flip"));
}

TEST(MeshIo, DropsFacesWithARepeatedOrInvalidIndexWithAWarning) {
  const auto dir = test::tempDir("mesh-io-drop");
  const auto path = writeFile(dir / "drop.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                              "f 1 2 3\nf 2 4 2\nf 2 4 9\nf 2 4 0\nf 3 2\nf 2 4 3\n");
  const auto result = readMesh(path);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0],
            quoted(path) +
                ": dropped 4 of 6 faces: 1 with fewer than 3 corners, 1 with a repeated vertex, "
                "2 with a vertex index out of range");
  EXPECT_EQ(faces(result.mesh->surface), (std::vector<std::array<int, 3>>{{0, 1, 2}, {1, 3, 2}}));
}

TEST(MeshIo, RefusesAFileWhoseFacesAreAllDropped) {
  const auto dir = test::tempDir("mesh-io-drop-all");
  const auto path = writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n");
  EXPECT_EQ(readError(path),
            quoted(path) + ": none of its 1 face is usable: 1 with a repeated vertex");
}

TEST(MeshIo, CountsWhatOpenMeshReadersDropAndTriangulate) {
  const auto dir = test::tempDir("mesh-io-openmesh-drops");
  const auto ply = writeFile(dir / "drop.ply",
                             "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 3\n"
                             "property list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 0 0\n3 0 1 2\n3 1 3 1\n4 1 4 3 2\n");
  const auto fromPly = readMesh(ply);
  EXPECT_EQ(faces(fromPly.mesh->surface),
            (std::vector<std::array<int, 3>>{{0, 1, 2}, {1, 4, 3}, {1, 3, 2}}));
  ASSERT_EQ(fromPly.warnings.size(), 2u);
  EXPECT_TRUE(contains(fromPly.warnings[0], "dropped 1 of 3 faces: 1 with a repeated vertex"));
  EXPECT_TRUE(contains(fromPly.warnings[1], "triangulated 1 polygon"));

  // OpenMesh's STL reader skips a facet whose corners merge without telling the importer.
  const auto stl = writeFile(dir / "drop.stl",
                             "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                             "vertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n"
                             "vertex 0 0 0\nvertex 1 0 0\nvertex 1 0 0\nendloop\nendfacet\n"
                             "endsolid t\n");
  const auto fromStl = readMesh(stl);
  EXPECT_EQ(fromStl.mesh->surface.n_faces(), 1u);
  ASSERT_EQ(fromStl.warnings.size(), 1u);
  EXPECT_EQ(fromStl.warnings[0],
            quoted(stl) + ": dropped 1 of 2 faces: 1 with corners at one position");
}

TEST(MeshIo, NamesTheFileForMissingUnreadableAndUnknownFiles) {
  const auto dir = test::tempDir("mesh-io-files");
  EXPECT_EQ(readError(dir / "missing.obj"), quoted((dir / "missing.obj")) + ": no such file");
  fs::create_directory(dir / "folder.obj");
  EXPECT_EQ(readError(dir / "folder.obj"),
            quoted((dir / "folder.obj")) + ": is a folder, not a mesh file");
  const auto xyz = writeFile(dir / "points.xyz", "0 0 0\n");
  EXPECT_EQ(readError(xyz),
            quoted(xyz) + ": unknown mesh format '.xyz' (supported: .obj, .ply, .off, .stl)");
  const auto garbage = writeFile(dir / "garbage.ply", "hello\n");
  EXPECT_EQ(readError(garbage),
            quoted(garbage) + ": is not a PLY file: it does not start with the line 'ply'");
  const auto shortVertex = writeFile(dir / "short.obj", "v 0 0\n");
  EXPECT_EQ(readError(shortVertex),
            quoted(shortVertex) + ": line 1: a vertex needs three numbers: 'v 0 0'");
  const auto badIndex = writeFile(dir / "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n");
  EXPECT_EQ(readError(badIndex), quoted(badIndex) + ": line 4: 'x' is not a vertex index");
}

TEST(MeshIo, KeepsOpenMeshQuietAndItsStreamsAsTheyWere) {
  const auto dir = test::tempDir("mesh-io-quiet");
  const auto path = writeFile(dir / "fin.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 5 5 5\n"
                              "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 2 2\n");
  const auto ply = writeFile(dir / "drop.ply",
                             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 2\n"
                             "property list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 1\n");
  ASSERT_TRUE(omerr().is_enabled());
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  const auto result = readMesh(path, {.repairNonManifold = true, .progress = {}});
  readMesh(ply);
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(err, "");
  EXPECT_EQ(out, "");
  EXPECT_EQ(result.warnings.size(), 2u);
  EXPECT_TRUE(omerr().is_enabled());
  EXPECT_TRUE(omlog().is_enabled());
  EXPECT_TRUE(omout().is_enabled());
}

TEST(MeshIo, ReadsFromSeveralThreadsAtOnce) {
  const auto dir = test::tempDir("mesh-io-threads");
  writeMesh(awkwardTetrahedron(), dir / "tet.ply");
  writeMesh(awkwardTetrahedron(), dir / "tet.stl");
  std::vector<std::thread> threads;
  std::vector<int> failures(4, 0);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 25; ++i) {
        try {
          const auto mesh = readMesh(dir / (t % 2 ? "tet.ply" : "tet.stl")).mesh;
          failures[t] += mesh->surface.n_faces() != 4 || mesh->surface.n_vertices() != 4;
        } catch (const std::exception&) {
          ++failures[t];
        }
      }
    });
  }
  for (auto& thread : threads)
    thread.join();
  EXPECT_EQ(failures, std::vector<int>(4, 0));
}

// ------------------------------------------------------------------------------------------------
// Writing and round trips.

TEST(MeshIo, ObjRoundTripIsBitExact) {
  const auto dir = test::tempDir("mesh-io-obj-round-trip");
  const Mesh original = extremeTetrahedron();
  writeMesh(original, dir / "tet.obj");
  const auto back = readMesh(dir / "tet.obj");
  EXPECT_TRUE(back.warnings.empty());
  ASSERT_EQ(back.mesh->surface.n_vertices(), 4u);
  for (int i = 0; i < 4; ++i) {
    const Vec3d a = pointVec(original.surface, i), b = pointVec(back.mesh->surface, i);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(std::signbit(a[k]), std::signbit(b[k]));
      EXPECT_EQ(a[k], b[k]) << "vertex " << i << " axis " << k;
    }
  }
  EXPECT_EQ(faces(back.mesh->surface), faces(original.surface));
  EXPECT_EQ(back.mesh->contentHash(), original.contentHash());

  // The shipped meshes come back exactly too.
  const auto bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  writeMesh(*bunny, dir / "bunny.obj");
  EXPECT_EQ(readMesh(dir / "bunny.obj").mesh->contentHash(), bunny->contentHash());
}

// PLY and OFF through OpenMesh 9 hold 32-bit floats: each coordinate comes back as exactly its
// nearest float, in the same vertex and face order.
class MeshIoFloatRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(MeshIoFloatRoundTrip, GivesEachCoordinateAsItsNearestFloat) {
  const auto dir = test::tempDir(std::string("mesh-io-round-trip-") + GetParam());
  const Mesh original = awkwardTetrahedron();
  const auto path = dir / (std::string("tet.") + GetParam());
  writeMesh(original, path);
  const auto back = readMesh(path);
  EXPECT_TRUE(back.warnings.empty());
  ASSERT_EQ(back.mesh->surface.n_vertices(), 4u);
  for (int i = 0; i < 4; ++i) {
    const Vec3d a = pointVec(original.surface, i), b = pointVec(back.mesh->surface, i);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(b[k], double(float(a[k]))) << i << " " << k;
  }
  EXPECT_EQ(faces(back.mesh->surface), faces(original.surface));
  // What was read from such a file is floats already, so a second round trip changes nothing.
  writeMesh(*back.mesh, path);
  EXPECT_EQ(readMesh(path).mesh->contentHash(), back.mesh->contentHash());
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshIoFloatRoundTrip, ::testing::Values("ply", "off", "PLY"));

// STL stores each triangle's corners, not shared vertices: OpenMesh merges equal corners back into
// vertices in order of first use, so vertex order may change while every face keeps its corners
// (as floats) and its winding.
TEST(MeshIo, StlRoundTripKeepsEveryTriangleAsFloats) {
  const auto dir = test::tempDir("mesh-io-stl");
  const Mesh original = awkwardTetrahedron();
  writeMesh(original, dir / "tet.stl");
  EXPECT_EQ(fs::file_size(dir / "tet.stl"), 84u + 50u * 4u);  // binary
  const auto back = readMesh(dir / "tet.stl");
  EXPECT_TRUE(back.warnings.empty());
  const TriMesh& mesh = back.mesh->surface;
  ASSERT_EQ(mesh.n_faces(), 4u);
  EXPECT_EQ(mesh.n_vertices(), 4u);
  const auto before = faces(original.surface), after = faces(mesh);
  for (std::size_t f = 0; f < 4; ++f) {
    for (int c = 0; c < 3; ++c) {
      const Vec3d a = pointVec(original.surface, before[f][c]), b = pointVec(mesh, after[f][c]);
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(b[k], double(float(a[k]))) << f << " " << c;
    }
  }
  EXPECT_EQ(meshStats(mesh).eulerCharacteristic, 2);

  // Two triangles touching only by position become one piece sharing an edge.
  TriMesh apart;
  std::vector<TriMesh::VertexHandle> v;
  for (const Vec3d& p : {Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(1, 0, 0),
                         Vec3d(0, 0, 0), Vec3d(0, -1, 0)})
    v.push_back(apart.add_vertex(p));
  apart.add_face(v[0], v[1], v[2]);
  apart.add_face(v[3], v[4], v[5]);
  writeMesh(Mesh(apart), dir / "apart.stl");
  const auto merged = readMesh(dir / "apart.stl").mesh;
  EXPECT_EQ(merged->surface.n_vertices(), 4u);
  EXPECT_EQ(meshStats(merged->surface).components, 1u);
}

TEST(MeshIo, WritesTheGivenFormatWhateverThePathIsCalled) {
  const auto dir = test::tempDir("mesh-io-format");
  const Mesh original = awkwardTetrahedron();
  writeMesh(original, dir / ".tet.tmp-1", MeshFormat::Obj);
  fs::rename(dir / ".tet.tmp-1", dir / "tet.obj");
  EXPECT_EQ(readMesh(dir / "tet.obj").mesh->contentHash(), original.contentHash());
  writeMesh(original, dir / "tet.obj", MeshFormat::Ply);  // the format wins over the name
  std::ifstream in(dir / "tet.obj");
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "ply");
}

TEST(MeshIo, WriteFailuresNameThePathAndLeaveNoFile) {
  const auto dir = test::tempDir("mesh-io-write-fail");
  const Mesh mesh = awkwardTetrahedron();
  const auto intoMissing = dir / "missing" / "tet.obj";
  try {
    writeMesh(mesh, intoMissing);
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_TRUE(contains(e.what(), quoted(intoMissing) + ": cannot be created"));
  }
  EXPECT_FALSE(fs::exists(dir / "missing"));

  try {
    writeMesh(mesh, dir / "tet.xyz");
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_TRUE(contains(e.what(), "unknown mesh format '.xyz'"));
  }

  TriMesh broken = mesh.surface;
  broken.set_point(TriMesh::VertexHandle(2), Vec3d(0, std::nan(""), 0));
  try {
    writeMesh(Mesh(broken), dir / "nan.obj");
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_TRUE(contains(e.what(), "not written: vertex 2 (0-based) has a non-finite"));
  }

  try {
    writeMesh(extremeTetrahedron(), dir / "far.ply");
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_TRUE(contains(e.what(),
                         "not written: vertex 1 (0-based) has a coordinate beyond the "
                         "32-bit float range of PLY"));
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(MeshIo, FormatsComeFromExtensionsInAnyCase) {
  EXPECT_EQ(meshFormatFromPath("a/b.obj"), MeshFormat::Obj);
  EXPECT_EQ(meshFormatFromPath("b.Ply"), MeshFormat::Ply);
  EXPECT_EQ(meshFormatFromPath("b.OFF"), MeshFormat::Off);
  EXPECT_EQ(meshFormatFromPath("b.stl"), MeshFormat::Stl);
  EXPECT_EQ(meshFormatFromPath("b.stla"), std::nullopt);
  EXPECT_EQ(meshFormatFromPath("obj"), std::nullopt);
  EXPECT_EQ(toString(MeshFormat::Stl), "STL");
}

// ------------------------------------------------------------------------------------------------
// Statistics, hash and summary of in-memory meshes.

TEST(MeshStats, CountsPiecesLoopsIsolatedAndNonFiniteVertices) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (const Vec3d& p :
       {Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(5, 0, 0), Vec3d(6, 0, 0),
        Vec3d(5, 1, 0), Vec3d(9, 9, 9), Vec3d(std::numeric_limits<double>::infinity(), 0, 0)})
    v.push_back(mesh.add_vertex(p));
  mesh.add_face(v[0], v[1], v[2]);
  mesh.add_face(v[3], v[4], v[5]);
  const MeshStats stats = meshStats(mesh);
  EXPECT_EQ(stats.vertices, 8u);
  EXPECT_EQ(stats.faces, 2u);
  EXPECT_EQ(stats.components, 2u);
  EXPECT_EQ(stats.boundaryLoops, 2u);
  EXPECT_EQ(stats.isolatedVertices, 2u);
  EXPECT_EQ(stats.nonFiniteVertices, 1u);
  EXPECT_EQ(stats.eulerCharacteristic, 8 - 6 + 2);
}

TEST(MeshStats, EmptyMeshHasNothing) {
  const MeshStats stats = meshStats(TriMesh());
  EXPECT_EQ(stats.vertices + stats.faces + stats.components + stats.boundaryLoops, 0u);
  EXPECT_EQ(stats.eulerCharacteristic, 0);
}

TEST(MeshValue, HashFollowsPointsFacesAndColours) {
  const Mesh a = awkwardTetrahedron();
  EXPECT_EQ(a.contentHash(), awkwardTetrahedron().contentHash());
  EXPECT_EQ(a.typeId(), "geobrush.Mesh");

  Mesh moved = awkwardTetrahedron();
  moved.surface.set_point(TriMesh::VertexHandle(3),
                          moved.surface.point(TriMesh::VertexHandle(3)) + Vec3d(0, 0, 1e-15));
  EXPECT_NE(moved.contentHash(), a.contentHash());

  // Same triangles, listed in another order.
  TriMesh reordered;
  for (int i = 0; i < 4; ++i)
    reordered.add_vertex(pointVec(a.surface, i));
  const auto f = faces(a.surface);
  for (int i : {1, 0, 2, 3}) {
    reordered.add_face(TriMesh::VertexHandle(f[i][0]), TriMesh::VertexHandle(f[i][1]),
                       TriMesh::VertexHandle(f[i][2]));
  }
  EXPECT_NE(Mesh(reordered).contentHash(), a.contentHash());

  const Mesh coloured(a.surface, std::vector<Rgb>(4, Rgb{1, 0, 0}));
  const Mesh otherColour(a.surface, std::vector<Rgb>(4, Rgb{0, 1, 0}));
  EXPECT_NE(coloured.contentHash(), a.contentHash());
  EXPECT_NE(coloured.contentHash(), otherColour.contentHash());

  // -0.0 and 0.0 are equal coordinates.
  Mesh negativeZero = awkwardTetrahedron();
  negativeZero.surface.set_point(TriMesh::VertexHandle(0), Vec3d(1.0 / 3, 0.0, 1e-30));
  EXPECT_EQ(negativeZero.contentHash(), a.contentHash());
}

TEST(MeshValue, SummaryCountsVerticesAndFaces) {
  EXPECT_EQ(awkwardTetrahedron().summary(), "4 vertices, 4 faces");
  TriMesh triangle;
  triangle.add_face(triangle.add_vertex({0, 0, 0}), triangle.add_vertex({1, 0, 0}),
                    triangle.add_vertex({0, 1, 0}));
  EXPECT_EQ(Mesh(triangle).summary(), "3 vertices, 1 face");
  EXPECT_EQ(readMesh(test::meshPath("bunny_small.obj")).mesh->summary(),
            "1839 vertices, 3674 faces");
}

}  // namespace
