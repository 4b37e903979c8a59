// GPU texture cloning paper, 3D retrieval: the gap between the pasted and the kept parts as a
// conforming constrained Delaunay triangulation with a minimum angle and a maximum area.
#include "cdt_stitch.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/domain_locator.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexInfo {
  int vertex = -1;        // the vertex of the result mesh; -1 for a Steiner point until added
  bool onTarget = false;  // on a target hole's outline: on the target surface, offset 0
};
struct FaceInfo {
  int nesting = -1;     // how many outlines enclose the face
  bool queued = false;  // in the order the gap's faces are added in
};
using VertexBase =
    CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel,
                                                CGAL::Delaunay_mesh_vertex_base_2<Kernel>>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<
                FaceInfo, Kernel, CGAL::Constrained_triangulation_face_base_2<Kernel>>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Exact predicates: crossing constraints are split at their (inexact) crossing, which
// insertOutlines detects, rather than undefined.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using KeepingMesher = CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria>;
using SplittingMesher = CGAL::Delaunay_mesher_2<Cdt, Criteria>;
using Handle = Cdt::Vertex_handle;
using Face = Cdt::Face_handle;

Vector2d uvOf(Handle v) {
  return {v->point().x(), v->point().y()};
}

// The outlines' vertices, each once, and their edges, as the triangulation's constraints.
struct Outlines {
  std::vector<int> vertices;  // vertices of the result mesh
  std::vector<Vector2d> uv;
  std::vector<std::array<int, 2>> edges;  // indices into `vertices`, along each loop
  std::size_t targetVertices = 0;         // the target's loops' come first
  double meanEdge = 0;                    // in the domain
};

Outlines collectOutlines(const OpenStitch& open) {
  Outlines outlines;
  double length = 0;
  for (const auto* loops : {&open.targetLoops, &open.patchLoops})
    for (const DomainLoop& loop : *loops) {
      const int first = int(outlines.vertices.size());
      const int n = int(loop.vertices.size());
      outlines.vertices.insert(outlines.vertices.end(), loop.vertices.begin(), loop.vertices.end());
      outlines.uv.insert(outlines.uv.end(), loop.uv.begin(), loop.uv.end());
      for (int k = 0; k < n; ++k) {
        outlines.edges.push_back({first + k, first + (k + 1) % n});
        length += (loop.uv[std::size_t((k + 1) % n)] - loop.uv[std::size_t(k)]).norm();
      }
      if (loops == &open.targetLoops) outlines.targetVertices = outlines.vertices.size();
    }
  if (!outlines.edges.empty()) outlines.meanEdge = length / double(outlines.edges.size());
  return outlines;
}

[[noreturn]] void refuseRegion(const std::string& message) {
  throw CdtStitchError("region", message);
}

// Inserts the outlines' vertices, in loop order, then their edges as constraints. Refuses
// outlines that touch (two vertices at one point of the domain) or cross (a constraint split at
// a crossing or by a vertex it passes through).
std::vector<Handle> insertOutlines(Cdt& cdt, const Outlines& outlines) {
  std::vector<Handle> handles;
  for (std::size_t k = 0; k < outlines.vertices.size(); ++k) {
    const Handle h = cdt.insert(Cdt::Point(outlines.uv[k].x(), outlines.uv[k].y()));
    if (h->info().vertex >= 0 && h->info().vertex != outlines.vertices[k])
      refuseRegion("the outlines of the paste and of the target's hole touch in the domain");
    h->info().vertex = outlines.vertices[k];
    h->info().onTarget = k < outlines.targetVertices;
    handles.push_back(h);
  }
  const std::size_t distinct = cdt.number_of_vertices();
  for (const auto& [a, b] : outlines.edges)
    cdt.insert_constraint(handles[std::size_t(a)], handles[std::size_t(b)]);
  bool whole = cdt.number_of_vertices() == distinct;
  for (const auto& [a, b] : outlines.edges)
    whole = whole && cdt.is_edge(handles[std::size_t(a)], handles[std::size_t(b)]);
  if (!whole)
    refuseRegion("the outlines of the paste and of the target's hole cross in the domain");
  return handles;
}

// Marks the gap: the faces an odd number of outlines encloses, counted by the constraints crossed
// on the way from the infinite face (between a hole's outline and R_in's, or between R_in's inner
// outline and an island of the target). Works for any refinement of the same constraints.
void markGap(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    f->info().nesting = -1;
  // Floods each level from where the one outside it met an outline: first in, first out, so that
  // every level is reached from the level just outside it.
  std::deque<std::pair<Face, int>> starts{{cdt.infinite_face(), 0}};
  while (!starts.empty()) {
    const auto [start, level] = starts.front();
    starts.pop_front();
    if (start->info().nesting >= 0) continue;
    start->info().nesting = level;
    std::vector<Face> flood{start};
    while (!flood.empty()) {
      const Face f = flood.back();
      flood.pop_back();
      for (int i = 0; i < 3; ++i) {
        const Face g = f->neighbor(i);
        if (g->info().nesting >= 0) continue;
        if (f->is_constrained(i)) {
          starts.emplace_back(g, level + 1);
        } else {
          g->info().nesting = level;
          flood.push_back(g);
        }
      }
    }
  }
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    f->set_in_domain(!cdt.is_infinite(f) && f->info().nesting % 2 == 1);
}

double gapArea(const Cdt& cdt) {
  double area = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain()) area += std::abs(cdt.triangle(f).area());
  return area;
}

// Runs `mesher` to its end. Refuses bounds whose refinement does not end within a multiple of the
// triangles they ask for.
template <typename Mesher>
void runMesher(Mesher& mesher, const Cdt& cdt, std::size_t limit) {
  mesher.init(true);  // the gap is marked in_domain already
  while (!mesher.is_refinement_done()) {
    mesher.step_by_step_refine_mesh();
    if (cdt.number_of_vertices() > limit) {
      throw CdtStitchError("min_angle_deg",
                           "the gap's refinement does not end: lower min_angle_deg");
    }
  }
}

// Delaunay refinement inside the gap; on the outlines too with `splitOutlines`, where they are
// encroached (from either side: CGAL's edge refinement does not look at the domain).
void refineGap(Cdt& cdt, double minAngleDegrees, double maxArea, bool splitOutlines,
               std::size_t outlineVertices) {
  const double sine = std::sin(minAngleDegrees * M_PI / 180);
  // The longest edge of a triangle whose edges are all at most this long has an area of at most
  // (sqrt 3 / 4) edge^2, the equilateral triangle's.
  const double edge = std::sqrt(4 * maxArea / std::sqrt(3.0));
  const double wanted = gapArea(cdt) / maxArea;
  if (!(wanted < 4e6)) {
    throw CdtStitchError("max_area", "the area bound asks for about " +
                                         std::to_string(std::size_t(wanted)) +
                                         " triangles in the gap: raise max_area");
  }
  const std::size_t limit =
      cdt.number_of_vertices() + 16 * std::size_t(wanted) + 8 * outlineVertices + 1024;
  if (splitOutlines) {
    SplittingMesher mesher(cdt, Criteria(sine * sine, edge));
    runMesher(mesher, cdt, limit);
  } else {
    KeepingMesher mesher(cdt, Criteria(sine * sine, edge));
    runMesher(mesher, cdt, limit);
  }
  markGap(cdt);  // the new faces inherit the mark; recounted for certainty
}

// +1 where the gap's triangles, counter-clockwise in the domain, join the mesh's boundary as they
// are; -1 where the mesh is oriented the other way in the domain.
int gapOrientation(const Cdt& cdt, const TriMesh& out) {
  int orientation = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int i = 0; i < 3; ++i) {
      if (!f->is_constrained(i)) continue;
      const auto a = TriMesh::VertexHandle(f->vertex(Cdt::ccw(i))->info().vertex);
      const auto b = TriMesh::VertexHandle(f->vertex(Cdt::cw(i))->info().vertex);
      const auto along = out.find_halfedge(a, b), back = out.find_halfedge(b, a);
      const int side = along.is_valid() && out.is_boundary(along) ? 1
                       : back.is_valid() && out.is_boundary(back) ? -1
                                                                  : 0;
      if (side == 0 || (orientation != 0 && side != orientation))
        refuseRegion("the gap between the outlines folds in the domain");
      orientation = side;
    }
  }
  return orientation;
}

// The points the refinement put on the outline edge from `a` to `b`, ordered from a, each with
// its parameter along the edge.
std::vector<std::pair<double, Handle>> pointsOnEdge(const Cdt& cdt, Handle a, Handle b) {
  const Vector2d from = uvOf(a), along = uvOf(b) - from;
  std::vector<std::pair<double, Handle>> points;
  for (Handle at = a; at != b;) {
    // The next vertex: across a constrained edge, added by the refinement or b, ahead on ab.
    Handle next;
    double nearest = std::numeric_limits<double>::infinity();
    auto around = cdt.incident_edges(at), end = around;
    do {
      if (cdt.is_infinite(around) || !cdt.is_constrained(*around)) continue;
      const Face f = around->first;
      const int i = around->second;
      const Handle w =
          f->vertex(Cdt::ccw(i)) == at ? f->vertex(Cdt::cw(i)) : f->vertex(Cdt::ccw(i));
      if (w != b && w->info().vertex >= 0) continue;
      const Vector2d d = uvOf(w) - from;
      const double t = d.dot(along) / along.squaredNorm();
      const double offLine = std::abs(along.x() * d.y() - along.y() * d.x()) / along.norm();
      const double current = (uvOf(at) - from).dot(along) / along.squaredNorm();
      if (t > current && t < nearest && offLine <= 1e-9 * along.norm()) {
        nearest = t;
        next = w;
      }
    } while (++around != end);
    if (next == Handle()) refuseRegion("an outline edge was split off its line");
    if (next != b) points.emplace_back(nearest, next);
    at = next;
  }
  return points;
}

// Splits each outline edge of `out` the refinement split, at the same points, and the face beside
// it with it; a point goes where it lies along the edge between the ends' positions (on the
// target's face beside a hole's outline, on the placed patch's beside R_in's). Returns whether a
// target face was split.
bool splitOutlineEdges(TriMesh& out, const Cdt& cdt, const Outlines& outlines,
                       const std::vector<Handle>& handles) {
  bool targetSplit = false;
  for (const auto& [ia, ib] : outlines.edges) {
    const Handle a = handles[std::size_t(ia)], b = handles[std::size_t(ib)];
    const auto points = pointsOnEdge(cdt, a, b);
    if (points.empty()) continue;
    targetSplit = targetSplit || a->info().onTarget;
    const Vector3d pa = pointOf(out, a->info().vertex), pb = pointOf(out, b->info().vertex);
    auto last = TriMesh::VertexHandle(a->info().vertex);
    const auto vb = TriMesh::VertexHandle(b->info().vertex);
    for (const auto& [t, w] : points) {
      auto h = out.find_halfedge(last, vb);
      if (!h.is_valid()) h = out.find_halfedge(vb, last);
      const auto added = out.split(out.edge_handle(h), toPoint((1 - t) * pa + t * pb));
      w->info().vertex = added.idx();
      w->info().onTarget = a->info().onTarget;
      last = added;
    }
  }
  return targetSplit;
}

// The offsets of the Steiner points: harmonic on the gap (cotangent weights in the domain), equal
// to `outlineOffset` on the outlines. Steiner point k carries -2 - k as its vertex until it is
// added.
std::vector<Vector3d> harmonicOffsets(const Cdt& cdt, const std::vector<Handle>& steiner,
                                      const std::function<Vector3d(Handle)>& outlineOffset) {
  const int n = int(steiner.size());
  if (n == 0) return {};
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(n, 3);
  auto unknown = [](Handle v) { return v->info().vertex < -1 ? -2 - v->info().vertex : -1; };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int k = 0; k < 3; ++k) {
      const Handle o = f->vertex(k), a = f->vertex(Cdt::ccw(k)), b = f->vertex(Cdt::cw(k));
      const Vector2d u = uvOf(a) - uvOf(o), w = uvOf(b) - uvOf(o);
      const double weight = 0.5 * u.dot(w) / std::abs(u.x() * w.y() - u.y() * w.x());
      for (const auto& [i, j] : {std::pair{a, b}, std::pair{b, a}}) {
        const int row = unknown(i);
        if (row < 0) continue;
        entries.emplace_back(row, row, weight);
        const int column = unknown(j);
        if (column >= 0)
          entries.emplace_back(row, column, -weight);
        else
          rhs.row(row) += weight * outlineOffset(j).transpose();
      }
    }
  }
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  const Eigen::MatrixX3d h = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !h.allFinite())
    refuseRegion("the offset over the gap has no harmonic solution: the gap is degenerate");
  std::vector<Vector3d> offsets;
  for (int i = 0; i < n; ++i)
    offsets.push_back(h.row(i).transpose());
  return offsets;
}

// Adds the Steiner points to `out` at X_T(w) + h(w).
void addSteinerPoints(TriMesh& out, const Cdt& cdt, const DomainLocator& locator) {
  std::vector<Handle> steiner;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (v->info().vertex < 0) {
      v->info().vertex = -2 - int(steiner.size());  // the unknown's index, until it is added
      steiner.push_back(v);
    }
  auto outlineOffset = [&](Handle v) -> Vector3d {
    if (v->info().onTarget) return Vector3d::Zero();  // the target itself
    return pointOf(out, TriMesh::VertexHandle(v->info().vertex)) - locator.locate(uvOf(v)).point;
  };
  const std::vector<Vector3d> offsets = harmonicOffsets(cdt, steiner, outlineOffset);
  for (std::size_t k = 0; k < steiner.size(); ++k) {
    const Vector3d p = locator.locate(uvOf(steiner[k])).point + offsets[k];
    steiner[k]->info().vertex = out.add_vertex({p.x(), p.y(), p.z()}).idx();
  }
}

// Adds the gap's triangles to `out`, breadth first from the outlines so that each meets the ones
// before it along an edge. Returns their faces.
std::vector<int> addGapFaces(TriMesh& out, const Cdt& cdt, int orientation) {
  std::vector<Face> order;
  std::vector<int> faces;
  auto enqueue = [&](Face f) {
    if (cdt.is_infinite(f) || !f->is_in_domain() || f->info().queued) return;
    f->info().queued = true;
    order.push_back(f);
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain() && (f->is_constrained(0) || f->is_constrained(1) || f->is_constrained(2)))
      enqueue(f);
  for (std::size_t next = 0; next < order.size(); ++next)
    for (int i = 0; i < 3; ++i)
      if (!order[next]->is_constrained(i)) enqueue(order[next]->neighbor(i));
  for (const Face f : order) {
    std::array<TriMesh::VertexHandle, 3> corners;
    for (int k = 0; k < 3; ++k)
      corners[std::size_t(k)] = TriMesh::VertexHandle(f->vertex(k)->info().vertex);
    if (orientation < 0) std::swap(corners[1], corners[2]);
    const auto face = out.add_face(corners[0], corners[1], corners[2]);
    if (!face.is_valid())
      refuseRegion("the gap's triangles could not be joined to the mesh around them");
    faces.push_back(face.idx());
  }
  return faces;
}

// Whether every outline edge, split or not, now has faces on both sides.
void requireClosed(const TriMesh& out, const Cdt& cdt) {
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e) {
    if (!cdt.is_constrained(*e)) continue;
    const auto va = TriMesh::VertexHandle(e->first->vertex(Cdt::ccw(e->second))->info().vertex),
               vb = TriMesh::VertexHandle(e->first->vertex(Cdt::cw(e->second))->info().vertex);
    const auto h = out.find_halfedge(va, vb);
    if (!h.is_valid() || out.is_boundary(out.edge_handle(h)))
      refuseRegion("an outline borders no gap: the outlines do not nest as a paste's do");
  }
}

}  // namespace

CdtGap closeGapByCdt(TriMesh& out, const OpenStitch& open, const DomainLocator& targetLocator,
                     const CdtStitchOptions& options) {
  if (!(options.minAngleDegrees >= 0 && options.minAngleDegrees <= 30))
    throw CdtStitchError("min_angle_deg", "the angle bound must lie between 0 and 30 degrees");
  if (!(options.maxArea >= 0 && std::isfinite(options.maxArea)))
    throw CdtStitchError("max_area", "the area bound must be 0 (automatic) or positive");
  CdtGap gap;
  const Outlines outlines = collectOutlines(open);
  if (outlines.edges.empty()) return gap;
  gap.maxArea = options.maxArea > 0 ? options.maxArea
                                    : std::sqrt(3.0) / 4 * outlines.meanEdge * outlines.meanEdge;
  if (!(gap.maxArea > 0)) refuseRegion("the outlines have no extent in the domain");

  Cdt cdt;
  const std::vector<Handle> handles = insertOutlines(cdt, outlines);
  markGap(cdt);
  const int orientation = gapOrientation(cdt, out);  // before the Steiner points: fails faster
  refineGap(cdt, options.minAngleDegrees, gap.maxArea, options.splitBoundary,
            outlines.vertices.size());
  std::size_t before = out.n_vertices();
  gap.targetFacesSplit = splitOutlineEdges(out, cdt, outlines, handles);
  gap.outlineVertices = out.n_vertices() - before;
  before = out.n_vertices();
  addSteinerPoints(out, cdt, targetLocator);
  gap.steinerVertices = out.n_vertices() - before;
  gap.faces = addGapFaces(out, cdt, orientation);
  gap.triangles = gap.faces.size();
  requireClosed(out, cdt);
  return gap;
}

CdtStitchResult cdtStitchPasteInto(TriMesh& out, const Region2D& region,
                                   const Parameterization& source, const TriMesh& draft,
                                   const Field2D* offset, const Parameterization& target,
                                   const StitchBase* base, const CdtStitchOptions& options,
                                   bool outHoldsOutside) {
  try {
    requireDraftOf(draft, source);
  } catch (const StitchError& e) {
    throw CdtStitchError("draft", e.what());
  }
  std::optional<StitchBase> ownBase;
  try {
    if (!base) base = &ownBase.emplace(stitchBase(target));
  } catch (const StitchError& e) {
    throw CdtStitchError("target", e.what());
  }
  std::optional<OpenStitch> open;
  try {
    open.emplace(stitchOpenLayoutInto(out, region, source, target, base, outHoldsOutside));
  } catch (const StitchError& e) {
    throw CdtStitchError("region", e.what());
  }
  try {
    placePatch(out, open->result.map, source, draft, offset, open->firstPatchVertex);
  } catch (const StitchError& e) {
    throw CdtStitchError("offset", e.what());
  }
  CdtStitchResult result;
  result.gap = closeGapByCdt(out, *open, *base->locator, options);
  result.paste = finishOpenStitch(out, std::move(*open));
  // The faces split beside the outlines are no gap faces, and a split target face leaves the
  // target's outside part changed.
  result.paste.map.seamFaces = result.gap.faces;
  result.paste.gapTriangles = result.gap.triangles;
  if (result.gap.targetFacesSplit) result.paste.startsWithOutside = false;
  return result;
}

}  // namespace geobrush
