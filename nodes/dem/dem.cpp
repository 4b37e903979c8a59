#include "dem.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <deque>
#include <limits>

#include "geobrush/exponential_map.hpp"
#include "geobrush/submesh.hpp"
#include "geobrush/surface_point.hpp"
#include "geobrush/text.hpp"

namespace geobrush {
namespace {

// Below this relative size an offset is rounding noise of the mesh's coordinates.
constexpr double kRoundoff = 1e-9;

void checkInput(const std::vector<Eigen::Vector2d>& sourceUv, const TargetDemOptions& o) {
  if (!std::isfinite(o.scale) || o.scale <= 0) {
    throw TargetDemError("scale",
                         "must be a finite number > 0 (target distance = scale x "
                         "domain distance), got " +
                             numberText(o.scale));
  }
  if (!std::isfinite(o.margin) || o.margin < 0) {
    throw TargetDemError("margin", "must be a finite number >= 0");
  }
  if (!std::isfinite(o.angleDegrees)) throw TargetDemError("angle", "must be a finite number");
  if (!o.origin.allFinite()) {
    throw TargetDemError("origin", "every coordinate must be a finite number");
  }
  if (!std::isfinite(o.originTolerance) || o.originTolerance < 0) {
    throw TargetDemError("origin", "the tolerance must be a finite number >= 0");
  }
  if (sourceUv.empty()) throw TargetDemError("source", "the source map has no vertices");
  for (std::size_t i = 0; i < sourceUv.size(); ++i) {
    if (!sourceUv[i].allFinite()) {
      throw TargetDemError("source",
                           "the source map of vertex " + std::to_string(i) + " is not finite");
    }
  }
}

// The bounding-box diagonal, refusing a vertex with a non-finite coordinate by name.
double finiteDiagonal(const TriMesh& mesh) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = toEigen(mesh.point(v));
    if (!p.allFinite()) {
      throw TargetDemError("mesh", "vertex " + std::to_string(v.idx()) +
                                       " of the target has a non-finite coordinate");
    }
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

void rejectOriginOnBoundary(const TriMesh& mesh, int face, const Eigen::Vector3d& point,
                            double diagonal) {
  for (auto h : mesh.fh_range(TriMesh::FaceHandle(face))) {
    const auto a = mesh.from_vertex_handle(h);
    const auto b = mesh.to_vertex_handle(h);
    const Eigen::Vector3d pa = toEigen(mesh.point(a)), pb = toEigen(mesh.point(b));
    const bool onEdge = mesh.is_boundary(mesh.opposite_halfedge_handle(h)) &&
                        distanceToSegment(point, pa, pb) <= kRoundoff * diagonal;
    const bool onVertex = mesh.is_boundary(a) && (point - pa).norm() <= kRoundoff * diagonal;
    if (onEdge || onVertex) {
      throw TargetDemError("origin",
                           "the origin lies on a boundary of the target mesh (near "
                           "vertex " +
                               std::to_string(a.idx()) + " " + pointText(pa) +
                               "): pick an origin inside the surface");
    }
  }
}

// The fixed vertices that must end up interior to P_t, and how many of their neighbours are
// still unfixed; growth may stop when no needed vertex has an unfixed neighbour.
class Needs {
 public:
  Needs(std::size_t vertices, bool boundaryAllowed)
      : unfixed_(vertices, -1), boundaryAllowed_(boundaryAllowed) {}

  void require(const TriMesh& mesh, const ExponentialMapGrowth& growth, int v) {
    if (unfixed_[v] >= 0) return;
    if (!boundaryAllowed_ && mesh.is_boundary(TriMesh::VertexHandle(v))) {
      throw TargetDemError(
          "scale", "the required domain runs off the target mesh at its boundary near vertex " +
                       std::to_string(v) + " " +
                       pointText(toEigen(mesh.point(TriMesh::VertexHandle(v)))) +
                       ": move the origin away from the boundary, or use a smaller scale or a "
                       "smaller source canvas");
    }
    int count = 0;
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
      count += !growth.isFixed(w.idx());
    unfixed_[v] = count;
    open_ += count > 0;
  }
  // `v` was just fixed: its needed neighbours have one unfixed neighbour fewer.
  void fixed(const TriMesh& mesh, int v) {
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
      if (unfixed_[w.idx()] > 0 && --unfixed_[w.idx()] == 0) --open_;
  }
  std::size_t open() const { return open_; }

 private:
  std::vector<int> unfixed_;  // -1: not needed
  bool boundaryAllowed_ = false;
  std::size_t open_ = 0;
};

double longestEdge(const TriMesh& mesh, int v) {
  const Eigen::Vector3d p = toEigen(mesh.point(TriMesh::VertexHandle(v)));
  double longest = 0;
  for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
    longest = std::max(longest, (toEigen(mesh.point(w)) - p).norm());
  return longest;
}

// Faces with three fixed corners, edge-connected to the origin face, in increasing order.
std::vector<int> regionFaces(const TriMesh& mesh, const ExponentialMapGrowth& growth,
                             int originFace, std::vector<char>& seen) {
  auto complete = [&](TriMesh::FaceHandle f) {
    return std::all_of(mesh.cfv_begin(f), mesh.cfv_end(f),
                       [&](auto v) { return growth.isFixed(v.idx()); });
  };
  std::vector<int> region{originFace};
  seen[originFace] = 1;
  for (std::size_t next = 0; next < region.size(); ++next) {
    for (auto g : mesh.ff_range(TriMesh::FaceHandle(region[next]))) {
      if (seen[g.idx()] || !complete(g)) continue;
      seen[g.idx()] = 1;
      region.push_back(g.idx());
    }
  }
  for (int f : region)
    seen[f] = 0;
  std::sort(region.begin(), region.end());
  return region;
}

// Vertices where the region's faces form more than one fan (the boundary touches itself).
std::vector<int> pinchedVertices(const TriMesh& mesh, const std::vector<int>& region,
                                 std::vector<char>& inRegion) {
  for (int f : region)
    inRegion[f] = 1;
  std::vector<int> borderOut, pinched;
  for (int f : region) {
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(f))) {
      const auto g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
      if (!g.is_valid() || !inRegion[g.idx()])
        borderOut.push_back(mesh.from_vertex_handle(h).idx());
    }
  }
  for (int f : region)
    inRegion[f] = 0;
  std::sort(borderOut.begin(), borderOut.end());
  for (std::size_t i = 1; i < borderOut.size(); ++i)
    if (borderOut[i] == borderOut[i - 1] && (pinched.empty() || pinched.back() != borderOut[i]))
      pinched.push_back(borderOut[i]);
  return pinched;
}

struct Region {
  Canvas canvas;
  // Surface vertices of every boundary loop but the outer one.
  std::vector<int> holeVertices;
};

// The canvas on `faces`; the outer loop is the one whose uv polygon has the largest area (holes
// in the outer band are small).
Region buildCanvas(const MeshPtr& target, const std::vector<int>& faces,
                   const ExponentialMapGrowth& growth, bool keepHoles) {
  const TriMesh& mesh = target->surface;
  Region r;
  Canvas& c = r.canvas;
  c.source = target;
  Submesh sub = extractSubmesh(mesh, faces);
  if (sub.unattachedFace >= 0) {
    throw TargetDemError("mesh", "face " + std::to_string(sub.unattachedFace) +
                                     " of the target canvas cannot be attached to its "
                                     "neighbours: the target mesh is not manifold there");
  }
  c.surface = std::move(sub.surface);
  c.sourceVertex = std::move(sub.sourceVertex);
  c.sourceFace = std::move(sub.sourceFace);

  std::vector<std::vector<int>> loops;
  std::vector<char> seen(c.surface.n_halfedges(), 0);
  for (auto start : c.surface.halfedges()) {
    if (!c.surface.is_boundary(start) || seen[start.idx()]) continue;
    std::vector<int> loop;
    auto h = start;
    do {
      seen[h.idx()] = 1;
      loop.push_back(c.surface.from_vertex_handle(h).idx());
      h = c.surface.next_halfedge_handle(h);
    } while (h != start);
    loops.push_back(std::move(loop));
  }
  if (loops.empty()) {
    throw TargetDemError("scale",
                         "the target canvas covers a whole closed surface: use a smaller "
                         "scale or a smaller source canvas");
  }
  auto area = [&](const std::vector<int>& loop) {
    double twice = 0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Eigen::Vector2d& a = growth.uv(c.sourceVertex[loop[i]]);
      const Eigen::Vector2d& b = growth.uv(c.sourceVertex[loop[(i + 1) % loop.size()]]);
      twice += a.x() * b.y() - a.y() * b.x();
    }
    return std::abs(twice);
  };
  std::size_t outer = 0;
  for (std::size_t i = 1; i < loops.size(); ++i)
    if (area(loops[i]) > area(loops[outer])) outer = i;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (i == outer) continue;
    // A loop of the mesh's own boundary is one of its holes.
    const bool meshHole = std::all_of(loops[i].begin(), loops[i].end(), [&](int v) {
      return mesh.is_boundary(TriMesh::VertexHandle(c.sourceVertex[v]));
    });
    if (keepHoles && meshHole) continue;
    for (int v : loops[i])
      r.holeVertices.push_back(c.sourceVertex[v]);
  }
  // As canvas_grow does: the loop starts at its lowest surface vertex.
  const auto& loop = loops[outer];
  const auto first = std::min_element(loop.begin(), loop.end()) - loop.begin();
  c.boundary.assign(loop.begin() + first, loop.end());
  c.boundary.insert(c.boundary.end(), loop.begin(), loop.begin() + first);
  return r;
}

MeshPtr checkedMesh(MeshPtr mesh) {
  if (!mesh || mesh->surface.n_faces() == 0) {
    throw TargetDemError("mesh", "the target mesh has no faces");
  }
  return mesh;
}

std::vector<Eigen::Vector3d> unitNormals(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> normals;
  normals.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d n = angleWeightedNormal(mesh, v);
    normals.push_back(n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero());
  }
  return normals;
}

}  // namespace

PreparedTarget::PreparedTarget(MeshPtr mesh)
    : mesh_(checkedMesh(std::move(mesh))),
      diagonal_(finiteDiagonal(mesh_->surface)),
      normals_(unitNormals(mesh_->surface)),
      locator_(mesh_->surface) {}

TargetDemResult targetExponentialMap(const MeshPtr& target,
                                     const std::vector<Eigen::Vector2d>& sourceUv,
                                     const TargetDemOptions& options) {
  checkInput(sourceUv, options);
  return targetExponentialMap(PreparedTarget(target), sourceUv, options);
}

namespace {

// The target canvas holding the domain disk of radius `required` around the origin.
TargetDemResult coveringCanvas(const PreparedTarget& prepared, const TargetDemOptions& options,
                               double required) {
  const MeshPtr& target = prepared.mesh();
  const TriMesh& mesh = target->surface;
  const double diagonal = prepared.diagonal();
  const double lambda = options.scale;

  const SurfacePoint snapped = prepared.nearest(options.origin);
  const double tolerance = options.originTolerance * diagonal;
  if (snapped.distance > tolerance) {
    throw TargetDemError("origin", "the origin " + pointText(options.origin) + " is " +
                                       numberText(snapped.distance) +
                                       " away from the target surface, farther than the "
                                       "tolerance " +
                                       numberText(tolerance) + ": pick a point on the surface");
  }
  rejectOriginOnBoundary(mesh, snapped.face, snapped.point, diagonal);

  auto surfaceNormal = [&](int v) -> Eigen::Vector3d {
    const Eigen::Vector3d& n = prepared.normal(v);
    if (n.isZero()) {
      throw TargetDemError("mesh", "target vertex " + std::to_string(v) +
                                       " has no surface normal (its faces are degenerate)");
    }
    return n;
  };
  std::array<Eigen::Vector3d, 3> corners, cornerNormals;
  std::vector<int> originCorners;
  for (auto v : mesh.fv_range(TriMesh::FaceHandle(snapped.face))) {
    corners[originCorners.size()] = toEigen(mesh.point(v));
    cornerNormals[originCorners.size()] = surfaceNormal(v.idx());
    originCorners.push_back(v.idx());
  }
  TargetDemResult result;
  try {
    result.origin = originFrame(corners, cornerNormals, snapped.point, options.angleDegrees);
  } catch (const DemError& e) {
    throw TargetDemError("origin", e.what());
  }

  ExponentialMapGrowth::Graph graph;
  graph.vertexCount = mesh.n_vertices();
  graph.point = [&](int v) { return toEigen(mesh.point(TriMesh::VertexHandle(v))); };
  graph.normal = surfaceNormal;
  graph.neighbours = [&](int v, std::vector<int>& out) {
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
      out.push_back(w.idx());
  };
  // SGW06: surface normals and steps rescaled to their 3D length.
  ExponentialMapGrowth growth(std::move(graph), result.origin, originCorners, true,
                              1e-12 * std::max(diagonal, std::numeric_limits<double>::min()));
  Needs needs(mesh.n_vertices(), options.keepHoles);
  const std::size_t limit = mesh.n_vertices() / 2;
  auto grow = [&] {
    while (needs.open() > 0 || !std::all_of(originCorners.begin(), originCorners.end(),
                                            [&](int v) { return growth.isFixed(v); })) {
      const int v = growth.fixNext();
      if (v < 0 || growth.order().size() > limit) {
        throw TargetDemError(
            "scale", "the domain to cover (radius " + numberText(required) + " x scale " +
                         numberText(lambda) + ") needs more than " +
                         (v < 0 ? std::string("the whole connected part") : std::string("half")) +
                         " of the target mesh (" + std::to_string(mesh.n_vertices()) +
                         " vertices), so the canvas would wrap around it: use a smaller scale, a "
                         "smaller source canvas or a larger target");
      }
      if (!growth.uv(v).allFinite()) {
        throw TargetDemError("mesh", "the map of target vertex " + std::to_string(v) +
                                         " is not finite (coincident vertices?)");
      }
      needs.fixed(mesh, v);
      if (growth.uv(v).norm() < lambda * required + longestEdge(mesh, v) / 2) {
        needs.require(mesh, growth, v);
      }
    }
  };

  std::vector<char> faceMarks(mesh.n_faces(), 0);
  Region region;
  for (;;) {
    grow();
    const std::vector<int> faces = regionFaces(mesh, growth, snapped.face, faceMarks);
    std::vector<int> defects = pinchedVertices(mesh, faces, faceMarks);
    if (defects.empty()) {
      region = buildCanvas(target, faces, growth, options.keepHoles);
      defects = region.holeVertices;
      if (defects.empty()) break;
    }
    // Section 3.1 needs one boundary loop: grow over the defects' neighbourhoods.
    for (int v : defects)
      needs.require(mesh, growth, v);
    if (needs.open() == 0) {
      throw TargetDemError(
          "mesh", "the target canvas encloses a hole of the target mesh near " +
                      pointText(toEigen(mesh.point(TriMesh::VertexHandle(defects.front())))) +
                      ": move the origin or use a smaller scale");
    }
  }

  Canvas& canvas = region.canvas;
  canvas.originPoint = snapped.point;
  canvas.originFace = static_cast<int>(
      std::lower_bound(canvas.sourceFace.begin(), canvas.sourceFace.end(), snapped.face) -
      canvas.sourceFace.begin());
  double best = std::numeric_limits<double>::infinity();
  for (auto v : canvas.surface.fv_range(TriMesh::FaceHandle(canvas.originFace))) {
    const double d = (toEigen(canvas.surface.point(v)) - snapped.point).norm();
    if (d < best || (d == best && v.idx() < canvas.originVertex)) {
      best = d;
      canvas.originVertex = v.idx();
    }
  }
  result.uv.reserve(canvas.sourceVertex.size());
  result.normal.reserve(canvas.sourceVertex.size());
  for (int v : canvas.sourceVertex) {
    result.uv.push_back(growth.uv(v) / lambda);
    result.normal.push_back(growth.normal(v));
  }
  result.canvas = std::move(canvas);
  result.requiredRadius = required;
  return result;
}

}  // namespace

TargetDemResult targetExponentialMap(const PreparedTarget& prepared,
                                     const std::vector<Eigen::Vector2d>& sourceUv,
                                     const TargetDemOptions& options) {
  checkInput(sourceUv, options);
  double sourceRadius = 0;
  for (const auto& u : sourceUv)
    sourceRadius = std::max(sourceRadius, u.norm());
  if (!(sourceRadius > 0)) {
    throw TargetDemError("source", "the source map is a single point: its canvas has no extent");
  }
  const double required = (1 + options.margin) * sourceRadius;
  if (options.preferredRadius > required) {
    try {
      return coveringCanvas(prepared, options, options.preferredRadius);
    } catch (const TargetDemError&) {
      // Too much of the target for the preferred disk: the required one alone.
    }
  }
  return coveringCanvas(prepared, options, required);
}

}  // namespace geobrush
