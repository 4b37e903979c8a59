#include "weld.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include <Eigen/Geometry>
#include <unsupported/Eigen/BVH>

#include "geobrush/border_loop.hpp"
#include "geobrush/cut_paste.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/loop_zip.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

std::string text(std::size_t n) {
  return std::to_string(n);
}

// The patch's only boundary loop; refuses a patch that cannot be joined along one loop.
std::vector<int> onlyPatchLoop(const TriMesh& patch) {
  if (patch.n_faces() == 0) throw WeldError("patch", "the patch has no faces");
  for (auto v : patch.vertices()) {
    if (patch.is_isolated(v))
      throw WeldError("patch", "patch vertex " + text(std::size_t(v.idx())) + " has no face");
    if (!patch.is_manifold(v))
      throw WeldError("patch", "patch vertex " + text(std::size_t(v.idx())) + " is not manifold");
  }
  auto loops = boundaryLoops(patch);
  if (loops.size() != 1)
    throw WeldError("patch", "the patch has " + text(loops.size()) +
                                 " boundary loops; it needs exactly one to join the hole");
  return std::move(loops.front());
}

std::vector<Vector3d> loopPoints(const TriMesh& mesh, const std::vector<int>& loop) {
  std::vector<Vector3d> points;
  points.reserve(loop.size());
  for (int v : loop)
    points.push_back(pointOf(mesh, v));
  return points;
}

// Twice the vector area of the closed polygon: the normal of the surface it bounds, scaled.
Vector3d vectorArea(const std::vector<Vector3d>& polygon) {
  Vector3d sum = Vector3d::Zero();
  for (std::size_t i = 0; i < polygon.size(); ++i)
    sum += polygon[i].cross(polygon[(i + 1) % polygon.size()]);
  return sum;
}

// A patch boundary vertex that becomes a border vertex: positions in the two loops.
struct Share {
  std::size_t border = 0, patch = 0;
};

// Each patch loop vertex within `tolerance` of its nearest border vertex, in patch loop order.
std::vector<Share> sharedVertices(const std::vector<Vector3d>& border,
                                  const std::vector<Vector3d>& patch, double tolerance) {
  std::vector<Share> shares;
  std::vector<long> takenBy(border.size(), -1);
  for (std::size_t j = 0; j < patch.size(); ++j) {
    std::size_t nearest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < border.size(); ++i)
      if (const double d = (border[i] - patch[j]).norm(); d < best) {
        best = d;
        nearest = i;
      }
    if (best > tolerance) continue;
    if (takenBy[nearest] >= 0)
      throw WeldError("patch", "patch boundary vertices at loop positions " +
                                   text(std::size_t(takenBy[nearest])) + " and " + text(j) +
                                   " both lie on border vertex " + text(nearest));
    takenBy[nearest] = long(j);
    shares.push_back({nearest, j});
  }
  return shares;
}

// The distance from p to the segment a b, and where along it its nearest point lies (0 at a).
std::pair<double, double> segmentDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return {(a + s * ab - p).norm(), s};
}

// Patch boundary points that lie on a border edge, away from its ends, split that edge there
// [ours]: the border gains a vertex the patch then shares, instead of a strip of slivers
// between a border edge and the patch vertices along it. `holed` and `border` are updated.
std::size_t splitBorderAtPatchPoints(TriMesh& holed, std::vector<int>& border,
                                     const std::vector<Vector3d>& patch, double tolerance) {
  std::size_t splits = 0;
  for (const Vector3d& p : patch) {
    const std::vector<Vector3d> points = loopPoints(holed, border);
    double nearestVertex = std::numeric_limits<double>::infinity();
    for (const Vector3d& b : points)
      nearestVertex = std::min(nearestVertex, (b - p).norm());
    if (nearestVertex <= tolerance) continue;
    for (std::size_t i = 0; i < border.size(); ++i) {
      const auto [distance, s] = segmentDistance(p, points[i], points[(i + 1) % border.size()]);
      if (distance > tolerance || s <= 0 || s >= 1) continue;
      const auto h = holed.find_halfedge(TriMesh::VertexHandle(border[i]),
                                         TriMesh::VertexHandle(border[(i + 1) % border.size()]));
      const auto v = holed.split(holed.edge_handle(h), toPoint(p));
      border.insert(border.begin() + std::ptrdiff_t(i + 1), v.idx());
      ++splits;
      break;
    }
  }
  return splits;
}

// Whether splitting a patch boundary edge at `tip` leaves both halves of its face facing as the
// face does: the face's third vertex sees the tip from the hole's side.
bool splitKeepsFacing(const TriMesh& patch, TriMesh::HalfedgeHandle edge, const Vector3d& tip) {
  if (patch.is_boundary(edge)) edge = patch.opposite_halfedge_handle(edge);
  const Vector3d a = pointOf(patch, patch.from_vertex_handle(edge));
  const Vector3d b = pointOf(patch, patch.to_vertex_handle(edge));
  const Vector3d x = pointOf(patch, patch.to_vertex_handle(patch.next_halfedge_handle(edge)));
  const Vector3d facing = (b - a).cross(x - a);
  return (tip - a).cross(x - a).dot(facing) > 0 && (b - tip).cross(x - tip).dot(facing) > 0;
}

// A patch boundary edge to split, and where.
struct EarSplit {
  TriMesh::EdgeHandle edge;
  Vector3d tip;
};

// Ears of the holed mesh [ours]: a border vertex c whose neighbours a and b along the border are
// joined by an edge of the holed mesh (its face a, c, b juts into the hole). A patch boundary edge
// on a and b passes behind c, so its face would overlap the ear: that edge is split at c, and the
// patch runs around the ear, sharing c too, where both halves of the face still face its way (else
// the weld refuses the overlap). `loop` is the patch's boundary loop.
std::vector<EarSplit> splitsAroundEars(const TriMesh& patch, const std::vector<int>& loop,
                                       const TriMesh& holed, const std::vector<int>& border,
                                       double tolerance) {
  const std::vector<Vector3d> borderPoints = loopPoints(holed, border);
  const std::size_t n = border.size();
  std::vector<long> borderAt(loop.size(), -1);
  std::vector<char> shared(n, 0);
  for (const Share& s : sharedVertices(borderPoints, loopPoints(patch, loop), tolerance)) {
    borderAt[s.patch] = long(s.border);
    shared[s.border] = 1;
  }
  std::vector<EarSplit> splits;
  for (std::size_t j = 0; j < loop.size(); ++j) {
    const long a = borderAt[j], b = borderAt[(j + 1) % loop.size()];
    if (a < 0 || b < 0 || n < 5) continue;  // on four vertices both arcs have two edges
    std::size_t ear = n;
    if ((std::size_t(b) + n - std::size_t(a)) % n == 2) ear = (std::size_t(a) + 1) % n;
    if ((std::size_t(a) + n - std::size_t(b)) % n == 2) ear = (std::size_t(b) + 1) % n;
    if (ear == n || shared[ear]) continue;
    const auto chord = holed.find_halfedge(TriMesh::VertexHandle(border[std::size_t(a)]),
                                           TriMesh::VertexHandle(border[std::size_t(b)]));
    if (!chord.is_valid()) continue;
    const auto edge = patch.find_halfedge(TriMesh::VertexHandle(loop[j]),
                                          TriMesh::VertexHandle(loop[(j + 1) % loop.size()]));
    if (splitKeepsFacing(patch, edge, borderPoints[ear]))
      splits.push_back({patch.edge_handle(edge), borderPoints[ear]});
  }
  return splits;
}

// The holed mesh's faces with a corner on the border.
std::vector<int> facesAroundBorder(const TriMesh& holed, const std::vector<int>& border) {
  std::vector<int> faces;
  for (int v : border)
    for (auto f : holed.vf_range(TriMesh::VertexHandle(v)))
      faces.push_back(f.idx());
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

// A patch face in the holed mesh's numbering where it shares the border: its corners (the border
// vertex where shared, else -1) and its points (the border vertex's where shared).
struct SeamFace {
  std::array<int, 3> holedCorner;
  Triangle3 points;
};

// Whether the patch face lies on an edge inside the holed mesh, which already has both of its
// faces.
bool onInnerEdge(const TriMesh& holed, const SeamFace& face) {
  for (std::size_t k = 0; k < 3; ++k) {
    const int a = face.holedCorner[k], b = face.holedCorner[(k + 1) % 3];
    if (a < 0 || b < 0) continue;
    const auto h = holed.find_halfedge(TriMesh::VertexHandle(a), TriMesh::VertexHandle(b));
    if (h.is_valid() && !holed.is_boundary(holed.edge_handle(h))) return true;
  }
  return false;
}

// Patch faces that overlap the holed mesh at the hole's border [ours]: a face on an edge inside
// the holed mesh, or one that covers part of a holed face around the border, seen along that
// face's normal, from within the face's longest edge of it. A template that reaches past a notch
// of the border leaves them; the weld removes them and zips the gap.
std::vector<int> overlappingPatchFaces(const TriMesh& patch, const std::vector<int>& loop,
                                       const TriMesh& holed, const std::vector<int>& border,
                                       double tolerance) {
  std::vector<int> holedVertex(patch.n_vertices(), -1);
  for (const Share& s :
       sharedVertices(loopPoints(holed, border), loopPoints(patch, loop), tolerance))
    holedVertex[std::size_t(loop[s.patch])] = border[s.border];
  using Box = Eigen::AlignedBox3d;
  const std::vector<int> ring = facesAroundBorder(holed, border);
  std::vector<Box> reach;
  std::vector<int> ids;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Triangle3 t = faceTriangle(holed, ring[i]);
    Box box;
    for (const Vector3d& p : t)
      box.extend(p);
    const double edge =
        std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    reach.emplace_back(box.min().array() - edge, box.max().array() + edge);
    ids.push_back(int(i));
  }
  const Eigen::KdBVH<double, 3, int> tree(ids.begin(), ids.end(), reach.begin(), reach.end());

  // Eigen's BVH visitor: tests the patch face against the ring faces whose reach holds it.
  struct Cover {
    const TriMesh& holed;
    const std::vector<int>& ring;
    const std::vector<Box>& reach;
    SeamFace face{};
    Box box;
    bool covers = false;
    bool intersectVolume(const Box& volume) const { return volume.intersects(box); }
    bool intersectObject(int i) {
      if (!reach[std::size_t(i)].intersects(box)) return false;
      const Triangle3 t = faceTriangle(holed, ring[std::size_t(i)]);
      covers = trianglesOverlapAlong((t[1] - t[0]).cross(t[2] - t[0]), t, face.points);
      return covers;
    }
  };
  std::vector<int> overlapping;
  for (auto f : patch.faces()) {
    Cover cover{holed, ring, reach, {}, {}, false};
    int k = 0;
    for (auto v : patch.fv_range(f)) {
      const int h = holedVertex[std::size_t(v.idx())];
      cover.face.holedCorner[std::size_t(k)] = h;
      cover.face.points[std::size_t(k++)] = h >= 0 ? pointOf(holed, h) : pointOf(patch, v);
    }
    for (const Vector3d& p : cover.face.points)
      cover.box.extend(p);
    if (!onInnerEdge(holed, cover.face)) {
      Eigen::BVIntersect(tree, cover);
      if (!cover.covers) continue;
    }
    overlapping.push_back(f.idx());
  }
  return overlapping;
}

// Whether moving patch vertex v to `to` keeps every face around it facing as it did.
bool moveKeepsFacing(const TriMesh& patch, TriMesh::VertexHandle v, const Vector3d& to) {
  for (auto f : patch.vf_range(v)) {
    Triangle3 before = faceTriangle(patch, f.idx()), after = before;
    std::size_t k = 0;
    for (auto u : patch.fv_range(f)) {
      if (u == v) after[k] = to;
      ++k;
    }
    const Vector3d n0 = (before[1] - before[0]).cross(before[2] - before[0]);
    const Vector3d n1 = (after[1] - after[0]).cross(after[2] - after[0]);
    if (n0.dot(n1) <= 0) return false;
  }
  return true;
}

// The patch as joined: the input patch with edges split around ears and overlaps removed, each of
// its vertices' input patch vertex (-1 for an ear's tip), and its boundary loop.
struct JoinedPatch {
  TriMesh mesh;
  std::vector<int> inputVertex;
  std::vector<int> loop;
  std::size_t earSplits = 0, trimmedFaces = 0, snappedVertices = 0;
};

// Border vertices left unshared by a trim take the nearest patch vertex the trim put on the
// patch's boundary, within half the vertex's shorter border edge, where moving it there turns no
// face over: the gap then closes by short edges instead of slivers past the vertex.
std::size_t snapExposedVertices(JoinedPatch& joined, const std::vector<char>& wasOnLoop,
                                const TriMesh& holed, const std::vector<int>& border,
                                double tolerance) {
  const std::vector<Vector3d> borderPoints = loopPoints(holed, border);
  std::vector<char> shared(border.size(), 0);
  for (const Share& s :
       sharedVertices(borderPoints, loopPoints(joined.mesh, joined.loop), tolerance))
    shared[s.border] = 1;
  std::vector<char> taken(joined.mesh.n_vertices(), 0);
  std::size_t snapped = 0;
  const std::size_t n = border.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (shared[i]) continue;
    const double reach = 0.5 * std::min((borderPoints[(i + 1) % n] - borderPoints[i]).norm(),
                                        (borderPoints[(i + n - 1) % n] - borderPoints[i]).norm());
    int nearest = -1;
    double best = reach;
    for (int v : joined.loop)
      if (const double d = (pointOf(joined.mesh, v) - borderPoints[i]).norm();
          !wasOnLoop[std::size_t(v)] && !taken[std::size_t(v)] && d < best) {
        best = d;
        nearest = v;
      }
    if (nearest < 0 ||
        !moveKeepsFacing(joined.mesh, TriMesh::VertexHandle(nearest), borderPoints[i]))
      continue;
    joined.mesh.set_point(TriMesh::VertexHandle(nearest), toPoint(borderPoints[i]));
    taken[std::size_t(nearest)] = 1;
    ++snapped;
  }
  return snapped;
}

// The patch's faces that overlap the holed mesh removed, and the border vertices this leaves
// unshared given the patch vertices it exposes nearby; false where none overlaps.
bool trimOverlaps(JoinedPatch& joined, const TriMesh& holed, const std::vector<int>& border,
                  double tolerance) {
  const std::vector<int> overlapping =
      overlappingPatchFaces(joined.mesh, joined.loop, holed, border, tolerance);
  if (overlapping.empty()) return false;
  std::vector<char> drop(joined.mesh.n_faces(), 0);
  for (int f : overlapping)
    drop[std::size_t(f)] = 1;
  std::vector<int> kept;
  for (std::size_t f = 0; f < drop.size(); ++f)
    if (!drop[f]) kept.push_back(int(f));
  Submesh rest = extractSubmesh(joined.mesh, kept);
  if (rest.unattachedFace >= 0 || kept.empty())
    throw WeldError("patch", "removing the " + text(overlapping.size()) +
                                 " patch faces that overlap the holed mesh at its border leaves "
                                 "no patch that joins it as a manifold");
  std::vector<char> onLoop(joined.mesh.n_vertices(), 0), wasOnLoop;
  for (int v : joined.loop)
    onLoop[std::size_t(v)] = 1;
  for (int v : rest.sourceVertex)
    wasOnLoop.push_back(onLoop[std::size_t(v)]);
  std::vector<int> inputVertex;
  for (int v : rest.sourceVertex)
    inputVertex.push_back(joined.inputVertex[std::size_t(v)]);
  joined.mesh = std::move(rest.surface);
  joined.inputVertex = std::move(inputVertex);
  try {
    joined.loop = onlyPatchLoop(joined.mesh);
  } catch (const WeldError& e) {
    throw WeldError(
        "patch", "with the " + text(overlapping.size()) +
                     " patch faces that overlap the holed mesh at its border removed, " + e.what());
  }
  joined.trimmedFaces = overlapping.size();
  joined.snappedVertices = snapExposedVertices(joined, wasOnLoop, holed, border, tolerance);
  return true;
}

// The input patch split around the hole's ears.
JoinedPatch splitAroundEars(const TriMesh& patch, const std::vector<int>& inputLoop,
                            const TriMesh& holed, const std::vector<int>& border,
                            double tolerance) {
  JoinedPatch joined{patch, {}, inputLoop, 0, 0, 0};
  for (auto v : patch.vertices())
    joined.inputVertex.push_back(v.idx());
  const std::vector<EarSplit> ears = splitsAroundEars(patch, inputLoop, holed, border, tolerance);
  for (const EarSplit& ear : ears) {
    joined.mesh.split(ear.edge, toPoint(ear.tip));
    joined.inputVertex.push_back(-1);
  }
  joined.earSplits = ears.size();
  if (!ears.empty()) joined.loop = onlyPatchLoop(joined.mesh);
  return joined;
}

// Whether the patch's loop runs along the border's (the patch faces the other way) rather than
// against it. Three or more shared vertices tell by their order, which must go once around both
// loops; fewer, by the loops' vector areas.
bool runsAlong(const std::vector<Share>& shares, const std::vector<Vector3d>& border,
               const std::vector<Vector3d>& patch) {
  if (shares.size() < 3) return vectorArea(border).dot(vectorArea(patch)) > 0;
  const std::size_t n = border.size();
  std::size_t forwards = 0, backwards = 0;
  for (std::size_t k = 0; k < shares.size(); ++k) {
    const std::size_t from = shares[k].border, to = shares[(k + 1) % shares.size()].border;
    forwards += (to + n - from) % n;
    backwards += (from + n - to) % n;
  }
  if (backwards == n) return false;
  if (forwards == n) return true;
  throw WeldError("patch",
                  "the patch's boundary vertices on the border are not in the border's cyclic "
                  "order");
}

// The border's vertices and the patch's (as result vertices), the shared ones by border order.
struct Seam {
  std::vector<int> border, patch;
  std::vector<Share> shares;
};

// The patch's vertices (the unshared ones added, in order) and faces appended to `out`.
std::vector<int> appendPatch(TriMesh& out, const TriMesh& patch, const std::vector<int>& loop,
                             const Seam& seam, bool flip) {
  std::vector<int> ids(patch.n_vertices(), -1);
  for (const Share& s : seam.shares)
    ids[std::size_t(loop[s.patch])] = seam.border[s.border];
  for (auto v : patch.vertices())
    if (ids[std::size_t(v.idx())] < 0)
      ids[std::size_t(v.idx())] = out.add_vertex(patch.point(v)).idx();
  for (auto f : patch.faces()) {
    std::array<TriMesh::VertexHandle, 3> c;
    int k = 0;
    for (auto v : patch.fv_range(f))
      c[std::size_t(k++)] = TriMesh::VertexHandle(ids[std::size_t(v.idx())]);
    if (flip) std::swap(c[1], c[2]);
    if (!out.add_face(c[0], c[1], c[2]).is_valid())
      throw WeldError("patch", "patch face " + text(std::size_t(f.idx())) +
                                   " cannot join the holed mesh as a manifold (it overlaps the "
                                   "mesh's faces at the shared vertices)");
  }
  return ids;
}

// The zip in space between result vertex chains (or loops), against the surfaces' normals.
template <typename Zip>
std::vector<std::array<int, 3>> zipInSpace(const TriMesh& out, const std::vector<Vector3d>& normals,
                                           const std::vector<int>& a, const std::vector<int>& b,
                                           Zip zip) {
  std::vector<Vector3d> na, nb;
  for (int v : a)
    na.push_back(normals[std::size_t(v)]);
  for (int v : b)
    nb.push_back(normals[std::size_t(v)]);
  const std::vector<Vector3d> pa = loopPoints(out, a), pb = loopPoints(out, b);
  return zip(a, b, SpaceZipMetric(pa, pb, na, nb), true);
}

// `loop` from position `from` forwards `count` edges.
std::vector<int> arc(const std::vector<int>& loop, std::size_t from, std::size_t count) {
  std::vector<int> vertices;
  for (std::size_t k = 0; k <= count; ++k)
    vertices.push_back(loop[(from + k) % loop.size()]);
  return vertices;
}

// The strip triangles: the whole loops zipped where nothing is shared, else each gap between
// consecutive shared vertices (the patch's arc runs back from the next shared vertex).
std::vector<std::array<int, 3>> gapTriangles(const TriMesh& out, const Seam& seam) {
  const std::vector<Vector3d> normals = vertexNormals(out);
  if (seam.shares.empty())
    return zipInSpace(out, normals, seam.patch, seam.border,
                      [](const auto&... args) { return zipLoops(args...); });
  const std::size_t n = seam.border.size(), m = seam.patch.size();
  std::vector<std::array<int, 3>> triangles;
  for (std::size_t k = 0; k < seam.shares.size(); ++k) {
    const Share& here = seam.shares[k];
    const Share& next = seam.shares[(k + 1) % seam.shares.size()];
    const std::size_t borderEdges = (next.border + n - here.border - 1) % n + 1;
    const std::size_t patchEdges = (here.patch + m - next.patch - 1) % m + 1;
    const auto gap = zipInSpace(out, normals, arc(seam.patch, next.patch, patchEdges),
                                arc(seam.border, here.border, borderEdges),
                                [](const auto&... args) { return zipChains(args...); });
    triangles.insert(triangles.end(), gap.begin(), gap.end());
  }
  return triangles;
}

std::vector<int> addStrip(TriMesh& out, const std::vector<std::array<int, 3>>& triangles) {
  std::vector<int> faces;
  for (const auto& t : triangles) {
    const auto f = out.add_face(TriMesh::VertexHandle(t[0]), TriMesh::VertexHandle(t[1]),
                                TriMesh::VertexHandle(t[2]));
    if (!f.is_valid())
      throw WeldError("patch", "the seam's triangle " + text(std::size_t(t[0])) + ", " +
                                   text(std::size_t(t[1])) + ", " + text(std::size_t(t[2])) +
                                   " would make the result non-manifold");
    faces.push_back(f.idx());
  }
  return faces;
}

void requireClosedSeam(const TriMesh& out, const Seam& seam) {
  for (const auto* loop : {&seam.border, &seam.patch})
    for (std::size_t i = 0; i < loop->size(); ++i) {
      const TriMesh::VertexHandle v((*loop)[i]);
      if (!out.is_manifold(v))
        throw WeldError("patch",
                        "the weld leaves vertex " + text(std::size_t(v.idx())) + " non-manifold");
    }
}

// Patch faces on an edge where the two loops coincide: the seam where no strip lies between.
std::vector<int> sharedEdgeFaces(const TriMesh& out, const Seam& seam) {
  std::vector<int> faces;
  const std::size_t n = seam.border.size();
  for (std::size_t k = 0; k < seam.shares.size(); ++k) {
    const Share& here = seam.shares[k];
    const Share& next = seam.shares[(k + 1) % seam.shares.size()];
    const bool oneEdge = (next.border + n - here.border) % n == 1 &&
                         (here.patch + seam.patch.size() - next.patch) % seam.patch.size() == 1;
    if (!oneEdge) continue;
    const auto h = out.find_halfedge(TriMesh::VertexHandle(seam.border[here.border]),
                                     TriMesh::VertexHandle(seam.border[next.border]));
    if (h.is_valid() && out.face_handle(h).is_valid()) faces.push_back(out.face_handle(h).idx());
  }
  std::sort(faces.begin(), faces.end());  // a face in a corner lies on two seam edges
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

// Pairs of a new face at the seam (a patch or strip face with a corner on either loop) and any
// face that it meets beyond their shared corners.
std::size_t newSeamIntersections(const TriMesh& out, const Seam& seam, std::size_t holedFaces) {
  std::vector<char> near(out.n_faces(), 0);
  for (const auto* loop : {&seam.border, &seam.patch})
    for (int v : *loop)
      for (auto f : out.vf_range(TriMesh::VertexHandle(v)))
        near[std::size_t(f.idx())] = std::size_t(f.idx()) >= holedFaces;
  std::vector<int> faces;
  for (std::size_t f = 0; f < near.size(); ++f)
    if (near[f]) faces.push_back(int(f));
  return selfIntersections(out, faces, 1e-12 * boundingDiagonal(out));
}

// targetVertex: the holed mesh's vertices; sourceVertex: the input patch's.
PasteMap pasteMap(const WeldResult& result, std::size_t holedVertices,
                  const std::vector<int>& patchIds, const std::vector<int>& inputVertex) {
  PasteMap map;
  map.targetVertex.assign(result.mesh.n_vertices(), -1);
  map.sourceVertex.assign(result.mesh.n_vertices(), -1);
  for (std::size_t v = 0; v < holedVertices; ++v)
    map.targetVertex[v] = int(v);
  for (std::size_t v = 0; v < patchIds.size(); ++v)
    if (inputVertex[v] >= 0) map.sourceVertex[std::size_t(patchIds[v])] = inputVertex[v];
  return map;
}

// The patch joined to the holed mesh (whose first holedVertices vertices are the input's, the
// rest split border edges): shared vertices, the patch turned to face the mesh's way, its faces
// appended and the gaps zipped; refuses a seam that is not manifold or whose new faces meet others.
WeldResult joinSeam(const TriMesh& holed, const std::vector<int>& border, const JoinedPatch& joined,
                    double tolerance, std::size_t holedVertices) {
  std::vector<int> patchLoop = joined.loop;
  const std::vector<Vector3d> patchPoints = loopPoints(joined.mesh, patchLoop);
  const std::vector<Vector3d> borderPoints = loopPoints(holed, border);
  Seam seam;
  seam.shares = sharedVertices(borderPoints, patchPoints, tolerance);

  WeldResult result;
  result.patchFlipped = runsAlong(seam.shares, borderPoints, patchPoints);
  if (result.patchFlipped) {
    std::reverse(patchLoop.begin(), patchLoop.end());
    for (Share& s : seam.shares)
      s.patch = patchLoop.size() - 1 - s.patch;
  }
  std::sort(seam.shares.begin(), seam.shares.end(),
            [](const Share& x, const Share& y) { return x.border < y.border; });
  seam.border = border;

  result.mesh = holed;
  const std::vector<int> patchIds =
      appendPatch(result.mesh, joined.mesh, patchLoop, seam, result.patchFlipped);
  for (int v : patchLoop)
    seam.patch.push_back(patchIds[std::size_t(v)]);
  const std::vector<int> strip = addStrip(result.mesh, gapTriangles(result.mesh, seam));
  requireClosedSeam(result.mesh, seam);

  if (const std::size_t meeting = newSeamIntersections(result.mesh, seam, holed.n_faces()))
    throw WeldError("patch", "the welded seam would make " + text(meeting) +
                                 " pairs of faces intersect: the patch does not fit the hole's "
                                 "border there");
  result.sharedVertices = seam.shares.size();
  result.earSplits = joined.earSplits;
  result.trimmedFaces = joined.trimmedFaces;
  result.snappedVertices = joined.snappedVertices;
  result.stripFaces = strip.size();
  result.map = pasteMap(result, holedVertices, patchIds, joined.inputVertex);
  result.map.seamFaces = sharedEdgeFaces(result.mesh, seam);
  result.map.seamFaces.insert(result.map.seamFaces.end(), strip.begin(), strip.end());
  return result;
}

}  // namespace

WeldResult weld(const TriMesh& holedMesh, const std::vector<int>& holeBorder, const TriMesh& patch,
                const WeldOptions& options) {
  if (const std::string problem = borderLoopProblem(holedMesh, holeBorder); !problem.empty())
    throw WeldError("border", "not a boundary loop of the holed mesh: " + problem);
  const std::vector<int> inputLoop = onlyPatchLoop(patch);
  const double tolerance = options.shareTolerance * boundingDiagonal(holedMesh);
  TriMesh holed = holedMesh;
  std::vector<int> border = holeBorder;
  const std::size_t borderSplits =
      splitBorderAtPatchPoints(holed, border, loopPoints(patch, inputLoop), tolerance);
  JoinedPatch joined = splitAroundEars(patch, inputLoop, holed, border, tolerance);
  WeldResult result;
  try {
    result = joinSeam(holed, border, joined, tolerance, holedMesh.n_vertices());
  } catch (const WeldError&) {
    // A patch that reaches over the holed mesh at the border (a template past a notch of it):
    // its overlapping faces are removed and the gap they leave zipped.
    if (!trimOverlaps(joined, holed, border, tolerance)) throw;
    result = joinSeam(holed, border, joined, tolerance, holedMesh.n_vertices());
  }
  result.borderSplits = borderSplits;
  return result;
}

}  // namespace geobrush
