// Values of the GeoBrush preprocess (paper sections 3.1, 4.2, 4.3): a canvas
// on a mesh, its parameterization, a shell cage and Green coordinates.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// A region of a mesh bounded by one loop; its inside may have any genus.
class Canvas final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Canvas";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  MeshPtr source;  // the whole mesh the canvas lies on
  // The canvas as a mesh of its own (the source's faces, vertices renumbered).
  TriMesh surface;
  std::vector<int> sourceVertex;  // surface vertex -> source vertex
  std::vector<int> sourceFace;    // surface face -> source face
  // Surface vertices of the boundary loop, in the order of the surface's
  // boundary halfedges.
  std::vector<int> boundary;
  Eigen::Vector3d originPoint = Eigen::Vector3d::Zero();  // on the surface
  int originFace = -1;                                    // surface face holding originPoint
  int originVertex = -1;                                  // surface vertex nearest originPoint
};
using CanvasPtr = std::shared_ptr<const Canvas>;

// Sets `boundary` to the surface's boundary loop from its lowest vertex, in the direction of its
// boundary halfedges (the surface has one loop), and the origin: originFace (a surface face),
// originPoint, and originVertex, the corner of that face nearest originPoint (ties: the lowest).
void setBoundaryAndOrigin(Canvas& canvas, int originFace, const Eigen::Vector3d& originPoint);

// G = 0 (the paper's Fig. 10a-b; hole filling): the canvas surface with every vertex at the
// origin, standing in for the draft G(P_s) where nothing is warped in.
MeshPtr zeroDraft(const Canvas& canvas);

class Context;
// What a paste node places: the Mesh on its optional "draft" input or, unconnected, the G = 0
// draft of the canvas of its "source" Parameterization, derived once per source
// (Context::derived).
MeshPtr draftOrZero(Context& ctx);

// An orthonormal frame: a normal and the directions of growing u and v.
struct Frame {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d uAxis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d vAxis = Eigen::Vector3d::UnitY();
};

// A map E: canvas -> R^2 (a discrete exponential map, original or
// generalized), with the normals it projected along.
class Parameterization final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Parameterization";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  CanvasPtr canvas;
  std::vector<Eigen::Vector2d> uv;      // per canvas surface vertex
  std::vector<Eigen::Vector3d> normal;  // per canvas surface vertex, unit
  Frame origin;                         // at the canvas origin; uv(origin) = (0, 0)
  // Relative to the source parameterization: the target's rotation of the
  // (u, v) axes in radians and its scale lambda (1 and 0 for a source).
  double rotation = 0;
  double scale = 1;
  // Per canvas face: 1 where the face is flipped in the parameter domain
  // (grown by a k-ring), used by ROI correction; empty when not computed.
  std::vector<std::uint8_t> reversedFaces;
};
using ParameterizationPtr = std::shared_ptr<const Parameterization>;

// A closed shell cage over a coarse triangulation C of the parameter domain:
// every vertex of C has a top and a bottom cage vertex, the two sheets are
// joined by a strip along C's boundary (paper section 4.3).
class Cage final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Cage";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  TriMesh mesh;                                     // closed, manifold, faces oriented outward
  std::vector<Eigen::Vector2d> domain;              // vertices of C
  std::vector<std::array<int, 3>> domainTriangles;  // faces of C
  std::vector<int> top;                             // C vertex -> cage vertex
  std::vector<int> bottom;                          // C vertex -> cage vertex
  std::vector<Frame> frames;  // per C vertex: the parameterization's frame there
};
using CagePtr = std::shared_ptr<const Cage>;

// Green coordinates of points with respect to a cage (Lipman, Levin,
// Cohen-Or 2008): point = sum_i phi_i v_i + sum_j psi_j n(t_j).
class GreenCoordinates final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.GreenCoordinates";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  // One point per row, stored row by row: applying the coordinates streams through each row once.
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  CagePtr cage;  // the cage they were computed against
  Matrix phi;    // points x cage vertices
  Matrix psi;    // points x cage faces
};
using GreenCoordinatesPtr = std::shared_ptr<const GreenCoordinates>;

}  // namespace geobrush
