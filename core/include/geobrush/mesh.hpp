// The mesh value: a double-precision OpenMesh triangle mesh.
#pragma once

// OpenMesh wants its IO header before any mesh header.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <Eigen/Core>

#include <array>
#include <vector>

#include "geobrush/value.hpp"

namespace geobrush {

struct MeshTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
};

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// RGB in [0, 1]; images store round(255 c), with no sRGB curve.
using Rgb = std::array<float, 3>;

class Mesh final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Mesh";

  Mesh() = default;
  // By reference: OpenMesh meshes have no move constructor, so taking one by value and moving it
  // in would copy it twice.
  explicit Mesh(const TriMesh& surface, std::vector<Rgb> vertexColors = {})
      : surface(surface), vertexColors(std::move(vertexColors)) {}

  std::string_view typeId() const override { return kTypeId; }
  // Hashes points, faces (as vertex index triples) and colours; O(n) per call.
  Hash contentHash() const override;
  std::string summary() const override;

  TriMesh surface;
  // Either empty or one colour per vertex (used by the renderer).
  std::vector<Rgb> vertexColors;
};

using MeshPtr = std::shared_ptr<const Mesh>;

// A vertex's point as an Eigen vector.
inline Eigen::Vector3d pointOf(const TriMesh& mesh, TriMesh::VertexHandle v) {
  const auto& p = mesh.point(v);
  return {p[0], p[1], p[2]};
}
inline Eigen::Vector3d pointOf(const TriMesh& mesh, int v) {
  return pointOf(mesh, TriMesh::VertexHandle(v));
}
// An OpenMesh point as an Eigen vector.
inline Eigen::Vector3d toEigen(const TriMesh::Point& p) {
  return {p[0], p[1], p[2]};
}
// An Eigen vector as an OpenMesh point.
inline TriMesh::Point toPoint(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

// Every vertex's point, in vertex order.
std::vector<Eigen::Vector3d> vertexPoints(const TriMesh& mesh);

// The length of the diagonal of the mesh's axis-aligned bounding box; 0 for a mesh without
// vertices. What tolerances relative to a mesh's size are measured in.
double boundingDiagonal(const TriMesh& mesh);

// The mean length of the mesh's edges; 0 without edges.
double meanEdgeLength(const TriMesh& mesh);

}  // namespace geobrush
