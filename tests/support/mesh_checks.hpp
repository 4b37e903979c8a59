// Geometric and topological measurements of triangle meshes, for checking results in tests.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "geobrush/mesh.hpp"

namespace geobrush::test {

// A tetrahedron on four corners; its faces point outward when the corners
// are ordered like (0,0,0), (1,0,0), (0,1,0), (0,0,1).
Mesh tetrahedron(const std::array<OpenMesh::Vec3d, 4>& corners);

// The box [lo, hi] with every side cut into n x n squares of two triangles,
// welded, faces outward: a cage for Green-coordinate tests.
TriMesh boxCage(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int n);

// An icosahedron split `levels` times (4^levels x 20 faces), its vertices pushed onto the unit
// sphere: a large closed test surface.
TriMesh icosphere(int levels);
// The square [0, 1]^2 at z = 0 cut into n x n squares of two triangles each, facing +z; vertex
// (i, j) is j (n + 1) + i.
TriMesh unitSquareGrid(int n);

double surfaceArea(const TriMesh& mesh);

// Sum of the signed volumes of the tetrahedra from the origin to each face: the enclosed volume
// of a closed mesh, positive when its faces are oriented outward.
double signedVolume(const TriMesh& mesh);

struct Topology {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t faces = 0;
  std::size_t boundaryHalfedges = 0;
  std::size_t boundaryLoops = 0;
  // Connected components of faces (isolated vertices are not counted).
  std::size_t components = 0;
  std::size_t isolatedVertices = 0;
  // Vertices whose faces do not form a single fan (e.g. two cones touching at a tip).
  std::size_t nonManifoldVertices = 0;
  // V - E + F = 2 - 2 genus - boundary loops, per component.
  long eulerCharacteristic = 0;
};
Topology topology(const TriMesh& mesh);

// The smallest interior angle of any face, in degrees (0 for a degenerate face).
double minAngleDegrees(const TriMesh& mesh);

// Pairs of distinct vertices closer than `tolerance`: unwelded seams show up here.
std::size_t closeVertexPairs(const TriMesh& mesh, double tolerance);

// Whether both have bit-identical points (in vertex order) and faces (as vertex index triples
// in face order).
bool bitIdentical(const TriMesh& a, const TriMesh& b);

// A copy of `mesh` with its first flippable interior edge flipped: the same counts, other
// connectivity.
TriMesh withAnEdgeFlipped(const TriMesh& mesh);

// Whether both have bit-identical points and the same halfedge structure, element for element:
// each vertex's and face's halfedge, and each halfedge's vertex, face, next and previous.
bool sameHalfedgeStructure(const TriMesh& a, const TriMesh& b);

// Every face as its vertex indices, starting from each face's first halfedge.
std::vector<std::array<int, 3>> faceIndices(const TriMesh& mesh);

// The length of every edge, in edge order.
std::vector<double> edgeLengths(const TriMesh& mesh);

}  // namespace geobrush::test
