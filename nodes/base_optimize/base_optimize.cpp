#include "base_optimize.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "base_mesh_ops.hpp"

namespace geobrush {
namespace {

void checkFinite(const TriMesh& base) {
  for (auto v : base.vertices()) {
    if (!pointOf(base, v).allFinite())
      throw std::invalid_argument("vertex " + std::to_string(v.idx()) +
                                  " has a coordinate that is not finite");
    if (!base.halfedge_handle(v).is_valid())
      throw std::invalid_argument("vertex " + std::to_string(v.idx()) + " is on no face");
  }
}

void checkOptions(const BaseOptimizeOptions& options) {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::out_of_range("base_optimize: " + what);
  };
  require(options.epsilon > 0 && std::isfinite(options.epsilon), "epsilon must be positive");
  require(options.referenceLength >= 0 && std::isfinite(options.referenceLength),
          "the reference length must be positive, or 0 for l_min");
  require(options.capAngleDeg >= 90 && options.capAngleDeg <= 180,
          "cap_angle_deg must lie in [90, 180]");
  require(options.aspectThreshold >= 0 && options.aspectThreshold <= 0.5,
          "aspect_threshold must lie in [0, 0.5]");
}

}  // namespace

double aspectRatio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const std::array<Eigen::Vector3d, 3> p{a, b, c};
  const double doubleArea = (b - a).cross(c - a).norm();
  double best = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d& from = p[k];
    const Eigen::Vector3d& to = p[(k + 1) % 3];
    const Eigen::Vector3d& apex = p[(k + 2) % 3];
    const Eigen::Vector3d edge = to - from;
    // The apex projects inside the edge: neither end angle is obtuse, the rectangle is e x h.
    if ((apex - from).dot(edge) < 0.0 || (apex - to).dot(-edge) < 0.0) continue;
    const double width = edge.norm();
    if (!(width > 0.0)) continue;
    const double height = doubleArea / width;
    best = std::max(best, std::min(width, height) / std::max(width, height));
  }
  return best;
}

double minimumEdgeLength(const TriMesh& mesh) {
  double shortest = 0.0;
  bool any = false;
  for (auto e : mesh.edges()) {
    const double length = edgeLength(mesh, e);
    shortest = any ? std::min(shortest, length) : length;
    any = true;
  }
  return shortest;
}

int checkedLoopLength(const TriMesh& base) {
  if (base.n_vertices() < 3 || base.n_faces() == 0)
    throw std::invalid_argument("a base needs at least one face");
  checkFinite(base);
  const auto start = base.find_halfedge(TriMesh::VertexHandle(0), TriMesh::VertexHandle(1));
  if (!start.is_valid() || !base.is_boundary(start))
    throw std::invalid_argument(
        "its boundary does not run from vertex 0 to vertex 1 (a base's "
        "loop is vertices 0..n-1 in the order of its boundary halfedges)");
  std::vector<int> loop;  // the vertices the boundary halfedges reach, from vertex 1 on
  auto h = start;
  do {
    loop.push_back(base.to_vertex_handle(h).idx());
    h = base.next_halfedge_handle(h);
  } while (h != start && loop.size() <= base.n_vertices());
  const int n = int(loop.size());
  for (int i = 0; i < n; ++i)
    if (loop[std::size_t(i)] != (i + 1) % n)
      throw std::invalid_argument("its boundary loop reaches vertex " +
                                  std::to_string(loop[std::size_t(i)]) + " where vertex " +
                                  std::to_string((i + 1) % n) +
                                  " was due (a base's loop is vertices 0..n-1 in order)");
  std::size_t boundaryHalfedges = 0;
  for (auto g : base.halfedges())
    boundaryHalfedges += base.is_boundary(g) ? 1 : 0;
  if (boundaryHalfedges != std::size_t(n))
    throw std::invalid_argument("it has more than one boundary loop (a base is a disc)");
  return n;
}

// Sec. 5.2: B from B0 by splitting (Eq. 2), slicing caps, collapsing needles and smoothing.
BaseOptimizeResult optimizeBase(const TriMesh& base, const BaseOptimizeOptions& options) {
  checkOptions(options);
  BaseOptimizeResult result;
  result.loopVertices = checkedLoopLength(base);
  result.referenceLength =
      options.referenceLength > 0.0 ? options.referenceLength : minimumEdgeLength(base);
  if (!(result.referenceLength > 0.0) || !std::isfinite(result.referenceLength))
    throw std::invalid_argument("its shortest edge (l_min, the reference of Eq. 2) has length 0");
  result.targetLength = options.epsilon * result.referenceLength;
  const double needed = vertexLowerBound(base, result.targetLength);
  if (needed > double(options.maxVertices)) {
    std::ostringstream message;
    message << "edges shorter than " << result.targetLength << " (epsilon " << options.epsilon
            << " x reference " << result.referenceLength << ") need at least " << needed
            << " vertices, more than the limit of " << options.maxVertices;
    throw BaseGrowthError(message.str());
  }
  result.minAngleBeforeDeg = minimumAngleDeg(base);

  TriMesh work = base;
  const double tau = options.aspectThreshold;
  result.splits = splitLongEdges(work, result.targetLength, options.maxVertices);
  result.slices = sliceCaps(work, options.capAngleDeg, tau, options.maxVertices);
  result.collapses = collapseNeedles(work, result.loopVertices, tau, result.targetLength);
  result.base = compactBase(work, result.loopVertices);
  smoothInterior(result.base, options.smoothIterations);
  // Smoothing may stretch an edge past Eq. 2's bound; split it again (no vertex is deleted).
  result.resplits = splitLongEdges(result.base, result.targetLength, options.maxVertices);
  result.splits += result.resplits;
  result.needlesLeft = countNeedles(result.base, tau);
  result.minAngleAfterDeg = minimumAngleDeg(result.base);
  return result;
}

}  // namespace geobrush
