// Free-form edits of a template by rigid and non-rigid handles with a shape function over geodesic
// distance (Freeform surface inpainting, section 5): x_new = alpha(x) T x + (1 - alpha(x)) x for a
// rigid handle, x_new = x + alpha(x) d_h(x) for a non-rigid one (d_h its vertices' translations
// carried over by Eqs. 4-6), with alpha(x) = profile(D(x,H) / (D(x,H) + D(x,L))) (Eq. 7), H the
// handle and L the template's boundary, D the graph distance on the symmetric kNN graph of the
// vertices (section 5.1).
#pragma once

#include <Eigen/Core>

#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "geobrush/geodesic_rbf.hpp"
#include "geobrush/knn_graph.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/rigid_motion.hpp"

namespace geobrush {

// A bad input or option. `option()` is the node's port or param it concerns: "template",
// "edits", "nonrigid_handle", "k", "profile" or "profile_samples".
class HandleEditError : public std::invalid_argument {
 public:
  HandleEditError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// The shape function alpha(t) of Eq. 7: 1 at t = 0 (on H), 0 at t = 1 (on L). The paper leaves
// it free; smoothstep (the default) has a zero slope at both ends; custom is drawn by the user.
enum class HandleProfile { Smoothstep, Linear, Cosine, Custom };

// "smoothstep", "linear", "cosine", "custom", as graph files name them.
const std::vector<std::string>& handleProfileNames();
// Throws HandleEditError("profile", ...) for an unknown name.
HandleProfile parseHandleProfile(std::string_view name);
// smoothstep 1 - 3t^2 + 2t^3, linear 1 - t, cosine (1 + cos(pi t)) / 2, for t in [0, 1]. Custom
// has no values of its own (HandleShape gives them): throws std::invalid_argument.
double profileValue(HandleProfile profile, double t);

// The shape function the edits use: a named profile, or a custom one from its samples, alpha at
// t = 0, 1/(m-1), ..., 1 joined by straight lines (creases allowed, as the paper says).
struct HandleShape {
  HandleShape(HandleProfile profile = HandleProfile::Smoothstep) : profile(profile) {}
  HandleProfile profile;
  std::vector<double> samples;  // with Custom
  double operator()(double t) const;
};

// A custom shape from its samples. Throws HandleEditError("profile_samples", ...) for fewer than
// 2, a non-finite one, or ends other than 1 at t = 0 and 0 at t = 1 (H moves by T, L stays).
HandleShape customShape(std::vector<double> samples);

// One rigid-handle edit (section 5): H is the vertices within graph distance `radius` of the
// vertex nearest `point`; T rotates by `angleDegrees` about `axis` through the handle's point,
// then translates by `translation`.
struct HandleEdit {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double radius = 0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double angleDegrees = 0;
};

// Numbers per edit row: px, py, pz, radius, tx, ty, tz, ax, ay, az, angle_deg.
inline constexpr std::size_t kEditRowSize = 11;

// The edits of `rows`, in order. Throws HandleEditError("edits", ...) naming the first bad row
// (counted from 1): a count that is not a multiple of 11, a non-finite number, a negative
// radius, or a zero axis with a non-zero angle.
std::vector<HandleEdit> editsFromRows(std::span<const double> rows);

// The template's boundary L and every vertex's graph distance D(x, L) to it.
struct BoundaryDistances {
  std::vector<int> boundary;       // L: the vertices on a boundary of the mesh, ascending
  std::vector<double> toBoundary;  // D(x, L) per vertex; kUnreached where no path leads to L
};

// Throws HandleEditError("template", ...) when the mesh has no boundary (L empty).
BoundaryDistances boundaryDistances(const TriMesh& mesh, const KnnGraph& graph);

// A handle placed on the template: what Eq. 7 needs of it, independent of T.
struct HandleRegion {
  int seed = 0;                  // the vertex nearest the edit's point: the handle's point
  std::vector<int> vertices;     // H, ascending
  std::vector<double> t;         // D(x,H) / (D(x,H) + D(x,L)) per vertex, in [0, 1]
  bool touchesBoundary = false;  // some vertex of H has D(x, L) = 0
};

// H and t for a handle at `point` with `radius` on the template whose graph and boundary
// distances are given. A vertex no path joins to H gets t = 1 (fixed); one joined to H but not
// to L gets t = 0 (moved with H), the limits of Eq. 7.
HandleRegion handleRegion(const TriMesh& mesh, const KnnGraph& graph,
                          const BoundaryDistances& boundary, const Eigen::Vector3d& point,
                          double radius);

// A rigid map x -> rotation x + offset.
// The edit's T: rotation about the axis through `pivot`, then the translation.
RigidMotion handleMotion(const HandleEdit& edit, const Eigen::Vector3d& pivot);

// One vertex of a non-rigid handle (section 5): the template vertex nearest `point`, moved by its
// own `translation`.
struct HandleVertexMove {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// Numbers per non-rigid handle row: px, py, pz, tx, ty, tz.
inline constexpr std::size_t kMoveRowSize = 6;

// The moves of `rows`, in order. Throws HandleEditError("nonrigid_handle", ...) naming the first
// bad row: a count that is not a multiple of 6 or a non-finite number.
std::vector<HandleVertexMove> movesFromRows(std::span<const double> rows);

// A non-rigid handle's effect on the template (section 5): H the vertices nearest the moves'
// points, each given its own translation, carried over the template by Gaussian RBFs of the graph
// distance (Eqs. 4-6; t_max the mean of D(h, L) over H [ours], the reach of the edit) and
// weighted by Eq. 7's alpha: each point moves by alpha(x) d_h(x), exactly 0 on L and the move's
// translation on H (to the solve's precision).
struct NonrigidHandleField {
  std::vector<int> handle;                    // H, in row order
  std::vector<Eigen::Vector3d> displacement;  // alpha(x) d_h(x) per vertex
  double tMax = 0;
  double conditionNumber = 0;  // of Eq. 6's A
};

// The field of `moves` on the unedited template whose graph and boundary distances are given;
// empty for no moves. Throws HandleEditError("nonrigid_handle", "row r: ...") for a move on L,
// on a vertex no path joins to L, or on the vertex of an earlier row.
NonrigidHandleField nonrigidHandleField(const TriMesh& unedited, const KnnGraph& graph,
                                        const BoundaryDistances& boundary,
                                        std::span<const HandleVertexMove> moves,
                                        const HandleShape& shape);

struct HandleEditOptions {
  int k = 8;  // neighbours per vertex in the kNN graph
  HandleShape profile;
  std::vector<HandleEdit> edits;           // applied in order
  std::vector<HandleVertexMove> nonrigid;  // one non-rigid handle, after the edits
};

struct HandleEditReport {
  int handles = 0;
  int verticesMoved = 0;       // vertices whose point changed, over all edits
  double maxDisplacement = 0;  // largest distance of a vertex from its input point
};

// Applies the edits in order to `mesh`, a copy of `unedited`, the template the regions were made
// on (one region per edit), then the non-rigid handle's field where one is given; the report
// compares the two. Every region's distances are those of the
// unedited template: a later edit acts on the points earlier edits moved, but H, D(x,H) and D(x,L)
// stay the template's, so changing one edit's T reuses every region. The pivot of an edit's
// rotation is its seed vertex where earlier edits left it. Points with alpha = 0 (on L) stay
// bit-identical; points with alpha = 1 (on H) get exactly T x. Throws HandleEditError("edits", "row
// r: ...") for a handle touching L.
HandleEditReport applyHandleEdits(const TriMesh& unedited, TriMesh& mesh,
                                  std::span<const HandleRegion* const> regions,
                                  const HandleEditOptions& options,
                                  const NonrigidHandleField* nonrigid = nullptr);

struct HandleEditResult {
  TriMesh mesh;
  HandleEditReport report;
};

// The whole edit on a template: its kNN graph, D(x, L), each edit's region, then the edits and
// the non-rigid handle.
// Throws HandleEditError naming the option or input at fault.
HandleEditResult editTemplate(const TriMesh& mesh, const HandleEditOptions& options);

// The kNN graph of the mesh's vertices. Throws HandleEditError("k", ...) for k < 1 and
// ("template", ...) for an empty mesh or a non-finite point.
KnnGraph vertexGraph(const TriMesh& mesh, int k);

}  // namespace geobrush
