// Values and shared steps of the topology-free cut-and-paste pipeline (Biermann-style cut and
// paste over a minimal-area base, ../papers/topology-free-cut-and-paste.txt): a feature F is
// encoded as points of a smooth base surface B spanning its boundary plus offsets in the base's
// local frames, and decoded over another base.
//
// Conventions every node of the pipeline keeps:
//  - A base mesh B over a canvas F: B's vertices 0..n-1 are F's boundary loop (F.boundary[i]) at
//    F's positions, in order; vertices added later (split points, interior points) follow. B's
//    faces are oriented like F's, so B's boundary halfedges run from F.boundary[i] towards
//    F.boundary[i + 1].
//  - A base's parameterization is a Parameterization whose canvas is B itself (canvasOfMesh).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// How a feature vertex's offset from its base point is kept.
enum class DetailMethod {
  FaceFrame,           // the paper's: all three components in the base face's own frame
  SmoothFrame,         // all three in a frame interpolated over the face from its corners'
  NormalDisplacement,  // the baseline: the height along the base's interpolated normal only
};

// Per vertex of a feature F: where it sits over the base B (a face of B and barycentric
// coordinates there, found through the common parameterization) and its offset from that point.
class DetailEncoding final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.DetailEncoding";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  ParameterizationPtr feature;  // P^F: its canvas is F
  ParameterizationPtr base;     // P^B: its canvas is B (canvasOfMesh)
  DetailMethod method = DetailMethod::SmoothFrame;
  std::vector<int> baseFace;                 // per F vertex: face of B
  std::vector<Eigen::Vector3d> barycentric;  // per F vertex, on that face's corners in fv order
  std::vector<Eigen::Vector3d> offset;       // per F vertex: (e1, e2, n) components of d
  // Pairs of F's faces that meet (intersection.hpp) where it lies: a pasted copy with more has
  // cut into itself.
  std::size_t selfIntersections = 0;
};
using DetailEncodingPtr = std::shared_ptr<const DetailEncoding>;

// A closed polyline on a mesh: one point per corner of a walked loop.
class SurfacePath final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.SurfacePath";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  MeshPtr mesh;                        // the mesh walked on
  std::vector<int> face;               // per point: the face of `mesh` it lies on
  std::vector<Eigen::Vector3d> point;  // per point
  double closingGap = 0;  // how far the walk's end landed from its start, in mesh units
  double scale = 1;       // lambda: target length over source length
};
using SurfacePathPtr = std::shared_ptr<const SurfacePath>;

// A face's local frame: e1 along its first edge (corner 0 to corner 1), n its unit normal,
// e2 = n x e1. Degenerate faces give an arbitrary orthonormal frame.
struct FaceFrame {
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
};
FaceFrame faceFrame(const std::array<Eigen::Vector3d, 3>& corners);

// Each vertex's angle-weighted normal (angleWeightedNormal), unit; zero where it cancels out.
std::vector<Eigen::Vector3d> vertexNormals(const TriMesh& mesh);

// What the offset methods read on a base, per vertex: the unit normal, and the unit tangent
// along which the base's parameterization grows u there (the faces' d x / d u, weighted by their
// area, made normal to the normal). A base moved onto another surface keeps its uv, so its
// tangents turn with it.
struct BaseFrameField {
  std::vector<Eigen::Vector3d> normal;
  std::vector<Eigen::Vector3d> tangent;
};
BaseFrameField baseFrameField(const TriMesh& base, const std::vector<Eigen::Vector2d>& uv);

// A face of a base with its corners' frames, in fv order.
struct BaseFace {
  std::array<Eigen::Vector3d, 3> point, normal, tangent;
};
BaseFace baseFace(const TriMesh& base, const BaseFrameField& field, int face);

// The offset of `point` from the face's point at barycentric `b`, in the method's components:
// FaceFrame in faceFrame(points); SmoothFrame in the frame whose normal and tangent are the
// corners' interpolated at b (the tangent made normal to the normal); NormalDisplacement
// (0, 0, height along the interpolated normal).
Eigen::Vector3d encodeOffset(const BaseFace& face, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& point, DetailMethod method);

// The inverse of encodeOffset over a (possibly moved) face, the offset scaled by `scale`.
Eigen::Vector3d decodeOffset(const BaseFace& face, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& offset, DetailMethod method, double scale);

// A disc-shaped mesh as a canvas of itself: identity vertex and face maps, `boundary` the loop
// from vertex 0 in the direction of its boundary halfedges, origin at vertex 0. Throws
// std::invalid_argument unless the mesh has exactly one boundary loop through vertex 0.
Canvas canvasOfMesh(const MeshPtr& mesh);

// The canvas of `faces` of `source` (any order, each once): the faces in increasing order, their
// vertices renumbered in increasing order, `boundary` from its lowest vertex. originFace is a
// face of `source` among `faces` holding originPoint. Throws std::invalid_argument when the faces
// are not bounded by exactly one loop or touch themselves at a vertex.
Canvas canvasFromFaces(const MeshPtr& source, std::vector<int> faces, int originFace,
                       const Eigen::Vector3d& originPoint);

// The similarity (rotation, uniform scale, translation; no reflection) that best maps `from` onto
// `to` in the least-squares sense, as a homogeneous 3x3 matrix: in complex numbers,
// q = mean(to) + z (p - mean(from)) with z = sum conj(p - mean) (q - mean) / sum |p - mean|^2
// (Umeyama 1991 in the plane); without `withScale`, z made unit (the best rigid motion). The
// translation alone when `from` has no spread.
Eigen::Matrix3d fitSimilarity2d(const std::vector<Eigen::Vector2d>& from,
                                const std::vector<Eigen::Vector2d>& to, bool withScale = true);

// The limit of umbrella smoothing: every vertex with movable[v] at the mean of its neighbours, the
// others fixed (the uniform-weight harmonic surface over them), by one sparse Cholesky solve.
// Components without a fixed vertex are left as they are.
void umbrellaSmoothToRest(TriMesh& mesh, const std::vector<char>& movable);

// Two sides of the closed polygon that are not neighbours and meet (touching counts), as their
// indices (side i runs from corner i to corner i + 1), or (-1, -1) for a simple polygon.
// O(m^2) in the polygon's corners.
std::pair<int, int> firstSelfCrossing(const std::vector<Eigen::Vector2d>& polygon);

// Whether p lies inside the closed polygon (nonzero winding) or within `tolerance` of its outline.
bool insidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p,
                   double tolerance);

// Umbrella smoothing (Jacobi): each vertex with movable[v] moves to the mean of its neighbours,
// `iterations` times.
void umbrellaSmooth(TriMesh& mesh, const std::vector<char>& movable, int iterations);

}  // namespace geobrush
