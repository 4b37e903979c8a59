// Rigid alignment of a template to a hole's border by ICP (Freeform surface inpainting, section
// 4.1): pair each border point b with its closest template point t_b, apply the rigid motion that
// minimizes the pairs' squared distances, and iterate; or solve once from user-given pairs.
#pragma once

#include <Eigen/Core>

#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"
#include "geobrush/point_neighbours.hpp"
#include "geobrush/rigid_motion.hpp"

namespace geobrush {

// The rotation and translation minimizing sum |R from_i + t - to_i|^2 (Kabsch's SVD solution;
// where the best orthogonal map is a reflection, the best proper rotation instead). With fewer
// than three non-collinear points the rotation is not determined and this returns one of the
// minimizers. Throws std::invalid_argument for no points or spans of different sizes.
RigidMotion fitRigidMotion(std::span<const Eigen::Vector3d> from,
                           std::span<const Eigen::Vector3d> to);

// `mesh` with every point moved by `motion`.
TriMesh moveRigidly(const TriMesh& mesh, const RigidMotion& motion);

// One correspondence: the border point `border` (an index into the border's points) and the
// template vertex `templateVertex`.
struct IcpPair {
  int border = 0;
  int templateVertex = 0;
  bool operator==(const IcpPair&) const = default;
};

struct TemplateIcpOptions {
  // Pair, reject, solve, apply: at most this many times; fewer once the pairs stop changing.
  int iterations = 5;
  // Leave pairs farther apart than this multiple of the median pair distance out of the fit; 0
  // keeps every pair.
  // Must be 0 or at least 1 (below 1 it could drop every pair).
  double reject = 3;
  // User-given pairs; when any are given the motion is solved once from them, without rejection.
  std::vector<IcpPair> explicitPairs;
  // Where the automatic pairing starts (e.g. frameAlignment); explicit pairs ignore it.
  RigidMotion initial;
  // Further starts, each run as `initial` is [ours]: the run that ends with its template closest
  // to every border point (rmsAllPairs; ties: the earlier start) is the result.
  std::vector<RigidMotion> otherStarts;
};

struct TemplateIcpResult {
  RigidMotion motion;  // maps the template onto the border
  // Every border point with its closest template vertex after the last motion, in border order
  // (the outliers only stay out of the fit: the warp must meet every border point); or the
  // explicit pairs.
  std::vector<IcpPair> pairs;
  int rejected = 0;        // pairs the last fit left out as outliers
  int iterations = 0;      // motions solved
  double rmsBefore = 0;    // RMS distance of the first pairs kept, template at `initial`
  double rmsAfter = 0;     // RMS distance of the pairs the last fit kept, template moved
  double rmsAllPairs = 0;  // RMS distance of `pairs`, template moved
  int start = 0;           // the start the result came from: 0 `initial`, i + 1 otherStarts[i]
};

// A bad input. `option()` names what to change: "template", "border", "iterations", "reject"
// or "explicit_pairs".
class TemplateIcpError : public std::invalid_argument {
 public:
  TemplateIcpError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// A start for ICP from anywhere [ours]: the template's vertex centroid moved onto the border's,
// its mean normal (its vector area) turned onto the surface's mean vertex normal along the
// border. A template with no mean normal to speak of (closed, or a tube) is only moved.
RigidMotion frameAlignment(const TriMesh& templateMesh, const TriMesh& holed,
                           const std::vector<int>& border);

// Numbers per explicit pair row: border index, template vertex.
constexpr std::size_t kIcpPairRowSize = 2;

// The pairs of `rows`, in order. Throws TemplateIcpError("explicit_pairs") for a count that is
// not a multiple of 2 or an entry that is not a non-negative integer.
std::vector<IcpPair> icpPairsFromRows(const std::vector<double>& rows);

// Aligns the template (its vertices indexed by `templatePoints`) to the border points. Being
// point-to-point ICP it settles in the nearest local minimum: it recovers the true motion when
// that moves each border point by less than about half the spacing of the template's vertices
// around it (a few rounds where the first pairs are partly wrong). Throws
// TemplateIcpError for an empty template or border, a non-finite border point, iterations < 0,
// reject outside {0} u [1, inf), or explicit pairs out of range or naming a border point twice.
TemplateIcpResult alignTemplate(const PointNeighbours& templatePoints,
                                std::span<const Eigen::Vector3d> border,
                                const TemplateIcpOptions& options);

}  // namespace geobrush
