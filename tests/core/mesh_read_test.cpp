// The mesh readers of each format (core/src/read_*.cpp): what they read, and what they refuse in
// files from other tools. Every refusal is one bounded message naming the file and the place;
// every declared size is checked against the file before anything is allocated for it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>

#include <sys/stat.h>

#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

using namespace geobrush;
using OpenMesh::Vec3d;

namespace {

namespace fs = std::filesystem;
using test::writeFile;

std::string readError(const fs::path& path) {
  try {
    readMesh(path);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

Vec3d pointVec(const TriMesh& mesh, int index) {
  return mesh.point(TriMesh::VertexHandle(index));
}

template <typename T>
std::string bytesOf(std::initializer_list<T> values, bool bigEndian = false) {
  std::string bytes;
  for (T value : values) {
    std::string raw(sizeof(T), '\0');
    std::memcpy(raw.data(), &value, sizeof(T));
    if (bigEndian) std::reverse(raw.begin(), raw.end());
    bytes += raw;
  }
  return bytes;
}

const std::vector<std::array<int, 3>> kTetrahedronFaces{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

std::string plyHeader(const std::string& format, const std::string& vertexType,
                      const std::string& faceList) {
  return "ply\nformat " + format + " 1.0\ncomment made by hand\nelement vertex 4\nproperty " +
         vertexType + " x\nproperty " + vertexType + " y\nproperty uchar red\nproperty " +
         vertexType + " z\nelement face 4\nproperty list " + faceList +
         " vertex_indices\nproperty int material\nelement edge 1\nproperty int vertex1\n"
         "property int vertex2\nend_header\n";
}

// ------------------------------------------------------------------------------------------------
// What each format reads.

TEST(PlyReader, ReadsAsciiWithOtherPropertiesAndElementsSkipped) {
  const auto dir = test::tempDir("ply-ascii");
  const auto path = writeFile(dir / "tet.ply", plyHeader("ascii", "double", "uchar int") +
                                                   "0 0 9 0\n1 0 9 0\n0 1 9 0\n0.1 0 9 1e-30\n"
                                                   "3 0 2 1 7\n3 0 1 3 7\n3 0 3 2 7\n3 1 2 3 7\n"
                                                   "0 1\n");
  const auto result = readMesh(path);
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_EQ(test::faceIndices(result.mesh->surface), kTetrahedronFaces);
  // Doubles are kept as doubles.
  EXPECT_EQ(pointVec(result.mesh->surface, 3), Vec3d(0.1, 0, 1e-30));
}

TEST(PlyReader, ReadsBinaryOfEitherByteOrder) {
  const auto dir = test::tempDir("ply-binary");
  for (const bool big : {false, true}) {
    std::string body;
    const std::vector<std::array<float, 3>> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1f, 0, 1}};
    for (const auto& p : points)
      body +=
          bytesOf<float>({p[0], p[1]}, big) + std::string(1, '\x09') + bytesOf<float>({p[2]}, big);
    for (const auto& f : kTetrahedronFaces)
      body += bytesOf<std::uint16_t>({3}, big) + bytesOf<std::int32_t>({f[0], f[1], f[2], 7}, big);
    body += bytesOf<std::int32_t>({0, 1}, big);
    const auto format = big ? "binary_big_endian" : "binary_little_endian";
    const auto path = writeFile(dir / (std::string(format) + ".ply"),
                                plyHeader(format, "float", "ushort int") + body);
    const auto result = readMesh(path);
    EXPECT_TRUE(result.warnings.empty());
    EXPECT_EQ(test::faceIndices(result.mesh->surface), kTetrahedronFaces) << format;
    EXPECT_EQ(pointVec(result.mesh->surface, 3), Vec3d(double(0.1f), 0, 1)) << format;
  }
}

TEST(PlyReader, NamesTheHeaderLineItCannotRead) {
  const auto dir = test::tempDir("ply-header");
  const auto format = writeFile(dir / "format.ply", "ply\nformat binary_middle_endian 1.0\n");
  EXPECT_EQ(readError(format), test::quoted(format) +
                                   ": line 2: unknown PLY format 'binary_middle_endian' (ascii, "
                                   "binary_little_endian or binary_big_endian)");
  const auto type =
      writeFile(dir / "type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n");
  EXPECT_EQ(readError(type), test::quoted(type) + ": line 4: unknown property type 'quad'");
  const auto noXyz = writeFile(dir / "xy.ply",
                               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                               "property float y\nend_header\n0 0\n");
  EXPECT_EQ(readError(noXyz),
            test::quoted(noXyz) + ": line 3: the vertex element has no x, y and z properties");
  const auto word = writeFile(dir / "word.ply",
                              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                              "property float y\nproperty float z\nend_header\n0 zero 0\n");
  EXPECT_EQ(readError(word),
            test::quoted(word) + ": vertex 0 (0-based, line 8): 'zero' is not a number");
}

TEST(OffReader, ReadsVariantsCommentsAndCountsOnTheKeywordLine) {
  const auto dir = test::tempDir("off-variants");
  // Normals and colours after the position, a colour after a face, comments and blank lines.
  const auto path =
      writeFile(dir / "tet.off",
                "# a tetrahedron\nCNOFF 4 4 6\n\n0 0 0  0 0 1  1 0 0 1\n"
                "1 0 0  0 0 1  1 0 0 1 # corner\n0 1 0 0 0 1 1 0 0 1\n"
                "0.1 0 1 0 0 1 1 0 0 1\n3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const auto result = readMesh(path);
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_EQ(test::faceIndices(result.mesh->surface), kTetrahedronFaces);
  EXPECT_EQ(pointVec(result.mesh->surface, 3), Vec3d(double(0.1f), 0, 1));
}

TEST(OffReader, ReadsBinary) {
  const auto dir = test::tempDir("off-binary");
  std::string body = bytesOf<std::int32_t>({4, 4, 6}, true);
  for (const auto& p :
       std::vector<std::array<float, 3>>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1f, 0, 1}})
    body += bytesOf<float>({p[0], p[1], p[2], 0.5f, 0.5f, 0.5f, 1}, true);
  for (const auto& f : kTetrahedronFaces)
    body += bytesOf<std::int32_t>({3, f[0], f[1], f[2], 0}, true);
  const auto path = writeFile(dir / "tet.off", "COFF BINARY\n" + body);
  const auto result = readMesh(path);
  EXPECT_EQ(test::faceIndices(result.mesh->surface), kTetrahedronFaces);
  EXPECT_EQ(pointVec(result.mesh->surface, 3), Vec3d(double(0.1f), 0, 1));
  const auto cut = writeFile(dir / "cut.off", "OFF BINARY\n" + body.substr(0, 40));
  EXPECT_TRUE(test::contains(readError(cut), "declares 4 vertices and 4 faces, which do not fit"));
}

TEST(StlReader, ReadsSeveralAsciiSolidsMergingCornersInOrderOfFirstUse) {
  const auto dir = test::tempDir("stl-ascii");
  const std::string facet =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n"
      "  vertex 0 1 0\n endloop\nendfacet\n";
  const std::string other =
      "facet normal 0 0 -1\nouter loop\nvertex 1 0 0\nvertex -0 0 0\n"
      "vertex 0 -1 0\nendloop\nendfacet\n";
  const auto path = writeFile(dir / "two.stl",
                              "solid a\n" + facet + "endsolid a\nsolid b\n" + other + "endsolid");
  const auto result = readMesh(path);
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_EQ(test::faceIndices(result.mesh->surface),
            (std::vector<std::array<int, 3>>{{0, 1, 2}, {1, 0, 3}}));
}

TEST(StlReader, WarnsWhenAnAsciiFileEndsWithoutEndsolid) {
  const auto dir = test::tempDir("stl-no-endsolid");
  const auto path = writeFile(dir / "open.stl",
                              "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n");
  const auto result = readMesh(path);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0], test::quoted(path) +
                                    ": ends after 1 facet without 'endsolid': the file may be cut "
                                    "short");
}

// ------------------------------------------------------------------------------------------------
// Linking the faces into one mesh (core/src/mesh_link.cpp).

// The mesh add_face makes of `mesh`'s points and faces, added one by one in order.
TriMesh addedFaceByFace(const TriMesh& mesh) {
  TriMesh added;
  for (auto v : mesh.vertices())
    added.add_vertex(mesh.point(v));
  for (const auto& f : test::faceIndices(mesh))
    added.add_face(TriMesh::VertexHandle(f[0]), TriMesh::VertexHandle(f[1]),
                   TriMesh::VertexHandle(f[2]));
  return added;
}

// Whether the halfedges close around every face and the boundary, and circulating around each
// vertex from its halfedge passes every face that uses it.
::testing::AssertionResult linkedConsistently(const TriMesh& mesh) {
  for (auto h : mesh.halfedges()) {
    const auto next = mesh.next_halfedge_handle(h);
    if (!next.is_valid() || mesh.prev_halfedge_handle(next) != h ||
        mesh.from_vertex_handle(next) != mesh.to_vertex_handle(h) ||
        mesh.face_handle(next) != mesh.face_handle(h))
      return ::testing::AssertionFailure() << "halfedge " << h.idx() << " is not linked";
  }
  std::vector<int> corners(mesh.n_vertices(), 0);
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f))
      ++corners[std::size_t(v.idx())];
  for (auto v : mesh.vertices()) {
    if (!mesh.halfedge_handle(v).is_valid()) {
      if (corners[std::size_t(v.idx())] == 0) continue;
      return ::testing::AssertionFailure() << "vertex " << v.idx() << " has no halfedge";
    }
    int faces = 0;
    for (auto f : mesh.vf_range(v))
      faces += f.is_valid();
    bool boundaryOut = false;
    for (auto h : mesh.voh_range(v))
      boundaryOut |= mesh.is_boundary(h);
    if (faces != corners[std::size_t(v.idx())] ||
        boundaryOut != mesh.is_boundary(mesh.halfedge_handle(v)))
      return ::testing::AssertionFailure()
             << "vertex " << v.idx() << " circulates " << faces << " of its "
             << corners[std::size_t(v.idx())] << " faces";
  }
  return ::testing::AssertionSuccess();
}

std::string objOf(const TriMesh& mesh, const std::vector<std::array<int, 3>>& faces) {
  std::string text;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    text += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) +
            "\n";
  }
  for (const auto& f : faces)
    text += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
            std::to_string(f[2] + 1) + "\n";
  return text;
}

TEST(MeshLink, LinksEveryShippedMeshAsAddFaceDoes) {
  for (const char* name : {"armadillo.obj", "boot.obj", "bunny_scan.obj", "bunny_small.obj",
                           "cube.obj", "fandisk.obj", "knot.obj", "mech_holes_shark.obj",
                           "mountain.obj", "nefertiti.obj", "sphere.obj", "torus.obj"}) {
    const auto read = readMesh(test::meshPath(name)).mesh;
    const TriMesh& mesh = read->surface;
    EXPECT_TRUE(test::sameHalfedgeStructure(mesh, addedFaceByFace(mesh))) << name;
    EXPECT_TRUE(linkedConsistently(mesh)) << name;
  }
}

TEST(MeshLink, LinksFacesInAnyOrderAsAddFaceDoes) {
  const auto dir = test::tempDir("link-shuffled");
  const auto bunnyMesh = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const TriMesh& bunny = bunnyMesh->surface;
  auto faces = test::faceIndices(bunny);
  std::mt19937 random(7);
  std::shuffle(faces.begin(), faces.end(), random);
  for (auto& f : faces)
    std::rotate(f.begin(), f.begin() + random() % 3, f.end());
  const auto read = readMesh(writeFile(dir / "shuffled.obj", objOf(bunny, faces))).mesh;
  EXPECT_TRUE(test::sameHalfedgeStructure(read->surface, addedFaceByFace(read->surface)));
  EXPECT_TRUE(linkedConsistently(read->surface));

  // Without some faces, vertices where several fans meet appear; add_face may leave such a
  // vertex's halfedge on another of its boundary halfedges, but links the same.
  faces.resize(faces.size() - 40);
  const auto holed = readMesh(writeFile(dir / "holed.obj", objOf(bunny, faces))).mesh;
  const TriMesh& mesh = holed->surface;
  EXPECT_GT(test::topology(mesh).nonManifoldVertices, 0u);
  EXPECT_TRUE(linkedConsistently(mesh));
  const TriMesh added = addedFaceByFace(mesh);
  for (auto h : mesh.halfedges()) {
    ASSERT_EQ(mesh.next_halfedge_handle(h), added.next_halfedge_handle(h)) << h.idx();
    ASSERT_EQ(mesh.face_handle(h), added.face_handle(h)) << h.idx();
  }
}

TEST(MeshLink, AFanInScatteredOrderIsOneDisc) {
  // Many faces meeting at one vertex, in scattered order: add_face's walk around the vertex at
  // every face made such files take quadratic time.
  const int n = 3000;
  TriMesh points;
  points.add_vertex(Vec3d(0, 0, 0));
  for (int i = 0; i < n; ++i)
    points.add_vertex(Vec3d(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0));
  std::vector<std::array<int, 3>> fan;
  for (int i = 0; i < n; ++i)
    fan.push_back({0, 1 + i, 1 + (i + 1) % n});
  std::shuffle(fan.begin(), fan.end(), std::mt19937(3));
  const auto dir = test::tempDir("link-fan");
  const auto result = readMesh(writeFile(dir / "fan.obj", objOf(points, fan)));
  EXPECT_TRUE(result.warnings.empty());
  const TriMesh& mesh = result.mesh->surface;
  const test::Topology topology = test::topology(mesh);
  EXPECT_EQ(topology.boundaryLoops, 1u);
  EXPECT_EQ(topology.nonManifoldVertices, 0u);
  EXPECT_EQ(topology.eulerCharacteristic, 1);
  EXPECT_EQ(mesh.valence(TriMesh::VertexHandle(0)), unsigned(n));
  EXPECT_TRUE(test::sameHalfedgeStructure(mesh, addedFaceByFace(mesh)));
}

TEST(MeshLink, OpenFansMeetingAtAVertexStayJoinedThere) {
  // A bow tie, and a third triangle touching it at the same vertex.
  const auto dir = test::tempDir("link-bow-tie");
  const auto result = readMesh(writeFile(dir / "bow.obj",
                                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\n"
                                         "v 0 2 0\nv -1 2 0\nf 1 2 3\nf 1 4 5\nf 1 6 7\n"));
  EXPECT_TRUE(result.warnings.empty());
  const TriMesh& mesh = result.mesh->surface;
  EXPECT_EQ(mesh.n_vertices(), 7u);
  EXPECT_EQ(test::topology(mesh).nonManifoldVertices, 1u);
  EXPECT_TRUE(linkedConsistently(mesh));
  EXPECT_TRUE(mesh.is_boundary(TriMesh::VertexHandle(0)));
}

TEST(MeshLink, ASecondClosedFanAtAVertexIsSplitOff) {
  // Two square pyramids, apex to apex: each closes a fan around the shared apex.
  std::string obj = "v 0 0 0\n";
  for (int z : {1, -1})
    obj += "v 1 0 " + std::to_string(z) + "\nv 0 1 " + std::to_string(z) + "\nv -1 0 " +
           std::to_string(z) + "\nv 0 -1 " + std::to_string(z) + "\n";
  for (int i = 0; i < 4; ++i)
    obj += "f 1 " + std::to_string(2 + i) + " " + std::to_string(2 + (i + 1) % 4) + "\n";
  for (int i = 0; i < 4; ++i)
    obj += "f 1 " + std::to_string(6 + (i + 1) % 4) + " " + std::to_string(6 + i) + "\n";
  const auto dir = test::tempDir("link-cones");
  const auto path = writeFile(dir / "cones.obj", obj);
  EXPECT_TRUE(test::contains(readError(path),
                             "4 faces would make an edge or vertex non-manifold "
                             "or flip the orientation (the first is face 4 of "
                             "the file, 0-based)"));
  const auto repaired = readMesh(path, {.repairNonManifold = true, .progress = {}});
  const TriMesh& mesh = repaired.mesh->surface;
  EXPECT_EQ(mesh.n_vertices(), 9u + 12u);
  EXPECT_EQ(mesh.n_faces(), 8u);
  EXPECT_TRUE(mesh.status(TriMesh::FaceHandle(4)).fixed_nonmanifold());
  EXPECT_FALSE(mesh.status(TriMesh::FaceHandle(3)).fixed_nonmanifold());
  EXPECT_EQ(test::topology(mesh).nonManifoldVertices, 0u);
  EXPECT_TRUE(linkedConsistently(mesh));
}

// ------------------------------------------------------------------------------------------------
// Files that once hung the reader, exhausted memory or gave a wrong or unstable message, each the
// smallest that showed it (tests/data/bad_meshes/).

struct BadMesh {
  const char* file;
  const char* message;  // after "'path': "
};

void PrintTo(const BadMesh& bad, std::ostream* os) {
  *os << bad.file;
}

class BadMeshFile : public ::testing::TestWithParam<BadMesh> {};

TEST_P(BadMeshFile, IsRefusedWithOneMessageNamingTheFileAndThePlace) {
  const fs::path path = test::sourceDir() / "tests/data/bad_meshes" / GetParam().file;
  const std::string message = readError(path);
  EXPECT_EQ(message, test::quoted(path) + ": " + GetParam().message);
  // The same file gives the same message every time.
  EXPECT_EQ(readError(path), message);
}

INSTANTIATE_TEST_SUITE_P(
    Issue, BadMeshFile,
    ::testing::Values(
        // Once an endless loop printing "Unsupported entry type" without bound.
        BadMesh{"ply_without_end_header.ply", "the PLY header has no 'end_header' line"},
        // Once 15 GB of memory from a 157-byte file.
        BadMesh{"off_face_declares_2e9_corners.off",
                "line 9: face 0 (0-based) declares 2000000000 corners but its line is 16 bytes "
                "long: '2000000000 0 2 4'"},
        // Once a near-hang.
        BadMesh{"off_counts_beyond_file.off",
                "line 2 declares 50000000 vertices and 50000000 faces, but only 6 lines follow"},
        // Once std::bad_alloc as the whole message.
        BadMesh{"off_2e9_vertices.off",
                "line 2 declares 2000000000 vertices and 1 face, but only 4 lines follow"},
        BadMesh{"off_negative_count.off",
                "line 2: expected the counts of vertices, faces and edges, got '-3 1 0'"},
        BadMesh{"ply_ascii_2e9_vertices.ply",
                "line 3 declares 2000000000 'vertex' elements of at least 6 bytes each, but only "
                "26 bytes follow the header"},
        BadMesh{"ply_ascii_negative_count.ply",
                "line 3: an element needs a name and a count, got 'vertex -3'"},
        BadMesh{"ply_binary_2e9_vertices.ply",
                "line 3 declares 2000000000 'vertex' elements of at least 12 bytes each, but only "
                "49 bytes follow the header"},
        BadMesh{"ply_binary_list_beyond_file.ply",
                "face 0 (0-based, byte 203): a list of 2000000000 entries does not fit in the rest "
                "of the file"},
        // Once a count that changed from run to run.
        BadMesh{"off_garbage.off",
                "line 2: expected the counts of vertices, faces and edges, got "
                "'\\x01\\xff garbage \\x07'"},
        // Once "holds no vertices and no faces".
        BadMesh{"stl_binary_wrong_count.stl",
                "binary STL declares 3 triangles, which take 84 + 50 x 3 = 234 bytes, but the "
                "file has 134: it is cut short"},
        BadMesh{"stl_binary_truncated.stl",
                "binary STL declares 2 triangles, which take 84 + 50 x 2 = 184 bytes, but the "
                "file has 154: it is cut short"},
        // Once read without a word.
        BadMesh{"stl_ascii_truncated.stl",
                "ends inside facet 1 (0-based), at line 12 (byte 152): the file is cut short"}),
    [](const auto& info) {
      std::string name = info.param.file;
      return name.substr(0, name.find('.'));
    });

TEST(BadMeshFile, RandomBytesAfterABinaryPlyHeaderEndTheReader) {
  // Once an endless loop in the header reader.
  const auto dir = test::tempDir("ply-random");
  std::mt19937 random(20);
  std::string bytes = "ply\nformat binary_little_endian 1.0\n";
  for (int i = 0; i < 20000; ++i)
    bytes += static_cast<char>(random() & 0xFF);
  const auto path = writeFile(dir / "random.ply", bytes);
  EXPECT_TRUE(
      test::contains(readError(path), test::quoted(path) + ": line 3: unknown PLY header line"));
}

TEST(BadMeshFile, AFileWithoutFacesIsNamedAsSuch) {
  const auto dir = test::tempDir("no-faces");
  const auto empty = writeFile(dir / "empty.stl", "");
  EXPECT_EQ(readError(empty), test::quoted(empty) +
                                  ": is neither ASCII STL (it does not start with 'solid') nor "
                                  "binary STL (0 bytes, less than the 84-byte header)");
  const auto solid = writeFile(dir / "solid.stl", "solid a\nendsolid a\n");
  EXPECT_EQ(readError(solid), test::quoted(solid) + ": holds no vertices and no faces");
  const auto header = writeFile(dir / "header.stl", std::string(84, '\0'));
  EXPECT_EQ(readError(header), test::quoted(header) + ": holds no vertices and no faces");
}

TEST(BadMeshFile, QuotesAtMost200CharactersOfALineAndEscapesControlCharacters) {
  const auto dir = test::tempDir("long-line");
  const std::string line = "v 0 \x1b[31m" + std::string(10'000'000, '7') + std::string(1, '\0');
  const auto path = writeFile(dir / "long.obj", line + "\n");
  const std::string message = readError(path);
  EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
  EXPECT_TRUE(test::contains(message, "line 1: a vertex needs three numbers: 'v 0 \\x1b[31m777"));
  EXPECT_TRUE(test::contains(message, "... (10000010 bytes)'"));
  EXPECT_EQ(message.find('\x1b'), std::string::npos);
}

TEST(BadMeshFile, AFifoOrADeviceIsNotRead) {
  EXPECT_EQ(readError("/dev/zero"),
            "'/dev/zero': is not a regular file (a device, FIFO or socket), not a mesh file");
  const auto dir = test::tempDir("fifo");
  const auto fifo = dir / "pipe.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Opening a FIFO for reading would block until a writer comes.
  EXPECT_EQ(readError(fifo), test::quoted(fifo) +
                                 ": is not a regular file (a device, FIFO or socket), not a mesh "
                                 "file");
}

}  // namespace
