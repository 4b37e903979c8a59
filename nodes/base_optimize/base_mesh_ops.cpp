#include "base_mesh_ops.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <optional>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>

#include "base_optimize.hpp"
#include "geobrush/cut_paste.hpp"

namespace geobrush {
namespace {

using VertexHandle = TriMesh::VertexHandle;
using HalfedgeHandle = TriMesh::HalfedgeHandle;

std::array<Eigen::Vector3d, 3> corners(const TriMesh& mesh, TriMesh::FaceHandle f) {
  std::array<Eigen::Vector3d, 3> c;
  int k = 0;
  for (auto v : mesh.fv_range(f))
    c[std::size_t(k++)] = pointOf(mesh, v);
  return c;
}

double angleAt(const Eigen::Vector3d& apex, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = b - apex, w = c - apex;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

void throwIfTooMany(const TriMesh& mesh, std::size_t maxVertices) {
  if (mesh.n_vertices() >= maxVertices)
    throw BaseGrowthError("the base would need more than " + std::to_string(maxVertices) +
                          " vertices");
}

// Adds a vertex at `p` on edge `e`, splitting it and its faces.
VertexHandle splitAt(TriMesh& mesh, TriMesh::EdgeHandle e, const Eigen::Vector3d& p) {
  const VertexHandle v = mesh.add_vertex(toPoint(p));
  mesh.split(e, v);
  return v;
}

// The halfedge of face f opposite its corner with the largest angle, and that angle.
std::pair<HalfedgeHandle, double> oppositeLargestAngle(const TriMesh& mesh, TriMesh::FaceHandle f) {
  HalfedgeHandle best;
  double bestAngle = -1.0;
  for (auto h : mesh.fh_range(f)) {
    const Eigen::Vector3d apex = pointOf(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
    const double angle = angleAt(apex, pointOf(mesh, mesh.from_vertex_handle(h)),
                                 pointOf(mesh, mesh.to_vertex_handle(h)));
    if (angle > bestAngle) {
      bestAngle = angle;
      best = h;
    }
  }
  return {best, bestAngle};
}

bool isNeedleByEdges(const std::array<Eigen::Vector3d, 3>& c, double tau) {
  const double a = (c[1] - c[0]).norm(), b = (c[2] - c[1]).norm(), d = (c[0] - c[2]).norm();
  return std::min({a, b, d}) < tau * std::max({a, b, d});
}

// Which endpoint of an edge goes and where the survivor lands (Sec. 5.2, step 3).
struct CollapsePlan {
  HalfedgeHandle halfedge;  // from the vertex removed to the one kept
  Eigen::Vector3d target;
};

std::optional<CollapsePlan> planCollapse(const TriMesh& mesh, HalfedgeHandle h, int loopVertices) {
  VertexHandle a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
  const bool aBoundary = mesh.is_boundary(a), bBoundary = mesh.is_boundary(b);
  if (aBoundary && bBoundary) {
    // Only along the loop, removing a point added on a chord: the chord stays straight.
    if (!mesh.is_boundary(mesh.edge_handle(h))) return std::nullopt;
    if (a.idx() < loopVertices && b.idx() < loopVertices) return std::nullopt;
    if (a.idx() < loopVertices || (b.idx() >= loopVertices && b.idx() > a.idx())) std::swap(a, b);
  } else if (aBoundary) {
    std::swap(a, b);
  } else if (!bBoundary && b.idx() > a.idx()) {
    std::swap(a, b);  // two interior vertices: the higher index goes
  }
  CollapsePlan plan;
  plan.halfedge = mesh.find_halfedge(a, b);
  plan.target =
      (aBoundary || bBoundary) ? pointOf(mesh, b) : 0.5 * (pointOf(mesh, a) + pointOf(mesh, b));
  return plan;
}

// Whether moving the faces around both endpoints onto the target keeps every normal's side and
// every edge shorter than maxLength.
bool collapseKeepsShape(const TriMesh& mesh, const CollapsePlan& plan, double maxLength) {
  const VertexHandle gone = mesh.from_vertex_handle(plan.halfedge);
  const VertexHandle kept = mesh.to_vertex_handle(plan.halfedge);
  for (VertexHandle end : {gone, kept}) {
    for (auto w : mesh.vv_range(end))
      if (w != gone && w != kept && (pointOf(mesh, w) - plan.target).norm() >= maxLength)
        return false;
    for (auto f : mesh.vf_range(end)) {
      std::array<Eigen::Vector3d, 3> before{}, after{};
      bool vanishes = false;
      int k = 0;
      for (auto v : mesh.fv_range(f)) {
        before[std::size_t(k)] = pointOf(mesh, v);
        after[std::size_t(k++)] = (v == gone || v == kept) ? plan.target : pointOf(mesh, v);
        vanishes = vanishes || (v == (end == gone ? kept : gone));
      }
      if (vanishes || before == after) continue;  // gone with the edge, or not moved
      const Eigen::Vector3d n0 = (before[1] - before[0]).cross(before[2] - before[0]);
      const Eigen::Vector3d n1 = (after[1] - after[0]).cross(after[2] - after[0]);
      if (!(n0.dot(n1) > 0.0)) return false;
    }
  }
  return true;
}

// The halfedge of face f along its shortest edge (ties to the first in the face's order).
HalfedgeHandle shortestEdge(const TriMesh& mesh, TriMesh::FaceHandle f) {
  HalfedgeHandle best;
  double bestLength = 0.0;
  for (auto h : mesh.fh_range(f)) {
    const double length = edgeLength(mesh, mesh.edge_handle(h));
    if (!best.is_valid() || length < bestLength) {
      best = h;
      bestLength = length;
    }
  }
  return best;
}

double faceAspect(const TriMesh& mesh, TriMesh::FaceHandle f) {
  const auto c = corners(mesh, f);
  return aspectRatio(c[0], c[1], c[2]);
}

}  // namespace

double edgeLength(const TriMesh& mesh, TriMesh::EdgeHandle e) {
  const auto h = mesh.halfedge_handle(e, 0);
  return (pointOf(mesh, mesh.to_vertex_handle(h)) - pointOf(mesh, mesh.from_vertex_handle(h)))
      .norm();
}

double minimumAngleDeg(const TriMesh& mesh) {
  double smallest = 180.0;
  for (auto f : mesh.faces()) {
    const auto c = corners(mesh, f);
    for (int k = 0; k < 3; ++k)
      smallest = std::min(smallest, angleAt(c[std::size_t(k)], c[std::size_t((k + 1) % 3)],
                                            c[std::size_t((k + 2) % 3)]) *
                                        180.0 / M_PI);
  }
  return smallest;
}

int countNeedles(const TriMesh& mesh, double tau) {
  int count = 0;
  for (auto f : mesh.faces())
    count += faceAspect(mesh, f) <= tau ? 1 : 0;
  return count;
}

double vertexLowerBound(const TriMesh& mesh, double target) {
  double area = 0.0, boundaryVertices = 0.0;
  for (auto f : mesh.faces()) {
    const auto c = corners(mesh, f);
    area += 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).norm();
  }
  for (auto e : mesh.edges()) {
    if (!mesh.is_boundary(e)) continue;
    double pieces = 1.0;
    for (double length = edgeLength(mesh, e); length >= target && pieces < 1e300; length *= 0.5)
      pieces *= 2.0;
    boundaryVertices += pieces;
  }
  const double faces = area / (std::sqrt(3.0) / 4.0 * target * target);
  return std::max(double(mesh.n_vertices()), 0.5 * (faces + boundaryVertices) + 1.0);
}

// Sec. 5.2 step 1: midpoint splits of the longest edge until Eq. 2 holds.
int splitLongEdges(TriMesh& mesh, double target, std::size_t maxVertices) {
  std::priority_queue<std::pair<double, int>> queue;  // (length, edge): stale when lengths differ
  for (auto e : mesh.edges())
    if (const double length = edgeLength(mesh, e); length >= target) queue.emplace(length, e.idx());
  int splits = 0;
  while (!queue.empty()) {
    const auto [length, index] = queue.top();
    queue.pop();
    const TriMesh::EdgeHandle e(index);
    if (edgeLength(mesh, e) != length) continue;
    throwIfTooMany(mesh, maxVertices);
    const auto h = mesh.halfedge_handle(e, 0);
    const Eigen::Vector3d midpoint =
        0.5 * (pointOf(mesh, mesh.from_vertex_handle(h)) + pointOf(mesh, mesh.to_vertex_handle(h)));
    const VertexHandle v = splitAt(mesh, e, midpoint);
    ++splits;
    for (auto out : mesh.voh_range(v)) {
      const auto edge = mesh.edge_handle(out);
      if (const double l = edgeLength(mesh, edge); l >= target) queue.emplace(l, edge.idx());
    }
  }
  return splits;
}

// Sec. 5.2 step 2 (after Botsch and Kobbelt's slicing, locally): caps split at the apex's foot.
int sliceCaps(TriMesh& mesh, double capAngleDeg, double tau, std::size_t maxVertices) {
  const double capAngle = capAngleDeg * M_PI / 180.0;
  const std::size_t maxSlices = 4 * mesh.n_faces();
  std::deque<int> pending;
  for (auto f : mesh.faces())
    pending.push_back(f.idx());
  int slices = 0;
  while (!pending.empty() && std::size_t(slices) < maxSlices) {
    const TriMesh::FaceHandle f(pending.front());
    pending.pop_front();
    if (mesh.status(f).deleted()) continue;
    const auto [longest, angle] = oppositeLargestAngle(mesh, f);
    if (!(angle > capAngle) || isNeedleByEdges(corners(mesh, f), tau)) continue;
    const Eigen::Vector3d from = pointOf(mesh, mesh.from_vertex_handle(longest));
    const Eigen::Vector3d to = pointOf(mesh, mesh.to_vertex_handle(longest));
    const Eigen::Vector3d apex =
        pointOf(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(longest)));
    const double t = (apex - from).dot(to - from) / (to - from).squaredNorm();
    if (!(t > 0.0 && t < 1.0)) continue;
    throwIfTooMany(mesh, maxVertices);
    const VertexHandle v = splitAt(mesh, mesh.edge_handle(longest), from + t * (to - from));
    ++slices;
    for (auto g : mesh.vf_range(v))
      pending.push_back(g.idx());
  }
  return slices;
}

// Sec. 5.2 step 3: collapses the shortest edge of each face with an aspect ratio <= tau.
int collapseNeedles(TriMesh& mesh, int loopVertices, double tau, double maxLength) {
  std::deque<int> pending;
  std::vector<char> queued(mesh.n_faces(), 0);
  for (auto f : mesh.faces())
    if (faceAspect(mesh, f) <= tau) {
      pending.push_back(f.idx());
      queued[std::size_t(f.idx())] = 1;
    }
  int collapses = 0;
  while (!pending.empty()) {
    const TriMesh::FaceHandle f(pending.front());
    pending.pop_front();
    queued[std::size_t(f.idx())] = 0;
    if (mesh.status(f).deleted() || faceAspect(mesh, f) > tau) continue;
    const auto plan = planCollapse(mesh, shortestEdge(mesh, f), loopVertices);
    if (!plan || !mesh.is_collapse_ok(plan->halfedge) ||
        !collapseKeepsShape(mesh, *plan, maxLength))
      continue;
    const VertexHandle kept = mesh.to_vertex_handle(plan->halfedge);
    mesh.set_point(kept, toPoint(plan->target));
    mesh.collapse(plan->halfedge);
    ++collapses;
    // The faces around the survivor changed shape; so did their neighbours' chances to collapse.
    for (auto w : mesh.vv_range(kept))
      for (auto g : mesh.vf_range(w))
        if (!queued[std::size_t(g.idx())] && faceAspect(mesh, g) <= tau) {
          pending.push_back(g.idx());
          queued[std::size_t(g.idx())] = 1;
        }
  }
  return collapses;
}

TriMesh compactBase(const TriMesh& mesh, int loopVertices) {
  TriMesh out;
  std::vector<int> index(mesh.n_vertices(), -1);
  for (int v = 0; v < loopVertices; ++v)
    index[std::size_t(v)] = out.add_vertex(mesh.point(VertexHandle(v))).idx();
  for (auto v : mesh.vertices())
    if (v.idx() >= loopVertices) index[std::size_t(v.idx())] = out.add_vertex(mesh.point(v)).idx();
  for (auto f : mesh.faces()) {
    std::array<VertexHandle, 3> c;
    int k = 0;
    for (auto v : mesh.fv_range(f))
      c[std::size_t(k++)] = VertexHandle(index[std::size_t(v.idx())]);
    if (!out.add_face(c[0], c[1], c[2]).is_valid())
      throw std::logic_error("base_optimize: a face of the optimized base does not fit its mesh");
  }
  return out;
}

void smoothInterior(TriMesh& mesh, int iterations) {
  std::vector<char> movable(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices())
    movable[std::size_t(v.idx())] = mesh.is_boundary(v) ? 0 : 1;
  if (iterations < 0)
    umbrellaSmoothToRest(mesh, movable);
  else
    umbrellaSmooth(mesh, movable, iterations);
}

}  // namespace geobrush
