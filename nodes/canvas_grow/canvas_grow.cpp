#include "canvas_grow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "geobrush/submesh.hpp"
#include "geobrush/text.hpp"

namespace geobrush {
namespace {

// Below this relative size an offset is rounding noise of the mesh's coordinates.
constexpr double kRoundoff = 1e-9;

// The halfedges of a face in the order of its fv_range corners (their to-vertices), read directly
// because OpenMesh's circulators cost more than the work done per face in the loops below.
std::array<TriMesh::HalfedgeHandle, 3> faceHalfedges(const TriMesh& mesh, int f) {
  const auto h0 = mesh.halfedge_handle(TriMesh::FaceHandle(f));
  const auto h1 = mesh.next_halfedge_handle(h0);
  return {h0, h1, mesh.next_halfedge_handle(h1)};
}

// The corner vertices of every face.
std::vector<std::array<int, 3>> faceCorners(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> corners(mesh.n_faces());
  for (std::size_t f = 0; f < corners.size(); ++f) {
    const auto h = faceHalfedges(mesh, int(f));
    for (int i = 0; i < 3; ++i)
      corners[f][i] = mesh.to_vertex_handle(h[i]).idx();
  }
  return corners;
}

std::vector<Eigen::Vector3d> points(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> p;
  p.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices())
    p.push_back(toEigen(mesh.point(v)));
  return p;
}

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

void checkInput(const MeshPtr& source, const CanvasGrowOptions& options) {
  if (!source || source->surface.n_faces() == 0) {
    throw CanvasGrowError("mesh", "the mesh has no faces to paint on");
  }
  for (auto v : source->surface.vertices()) {
    if (!toEigen(source->surface.point(v)).allFinite()) {
      throw CanvasGrowError(
          "mesh", "vertex " + std::to_string(v.idx()) + " of the mesh has a non-finite coordinate");
    }
  }
  if (!options.origin.allFinite()) {
    throw CanvasGrowError("origin", "every coordinate must be a finite number");
  }
  if (!std::isfinite(options.originTolerance) || options.originTolerance < 0) {
    throw CanvasGrowError("origin", "the tolerance must be a finite number >= 0");
  }
  if (options.dabs.empty()) {
    throw CanvasGrowError("dabs", "nothing is painted: add at least one dab (x, y, z, radius)");
  }
  for (std::size_t i = 0; i < options.dabs.size(); ++i) {
    const CanvasDab& dab = options.dabs[i];
    if (!dab.center.allFinite() || !std::isfinite(dab.radius)) {
      throw CanvasGrowError("dabs", "dab " + std::to_string(i) + " has a non-finite entry");
    }
    if (dab.radius <= 0) {
      throw CanvasGrowError("dabs", "dab " + std::to_string(i) + " has radius " +
                                        numberText(dab.radius) + ": radii must be positive");
    }
  }
}

bool insideSomeDab(const Eigen::Vector3d& p, const std::vector<CanvasDab>& dabs) {
  return std::any_of(dabs.begin(), dabs.end(), [&](const CanvasDab& d) {
    return (p - d.center).squaredNorm() <= d.radius * d.radius;
  });
}

double boundingDiagonal(const std::vector<Eigen::Vector3d>& p) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& x : p) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return (hi - lo).norm();
}

// Throws when the snapped origin lies on a boundary edge of one of `faces`, naming the loop.
void rejectOriginOnBoundary(const TriMesh& mesh, const std::vector<int>& faces,
                            const Eigen::Vector3d& point, double diagonal) {
  for (int f : faces) {
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(f))) {
      const auto outside = mesh.opposite_halfedge_handle(h);
      if (!mesh.is_boundary(outside)) continue;
      const auto a = mesh.from_vertex_handle(h);
      const auto b = mesh.to_vertex_handle(h);
      if (distanceToSegment(point, toEigen(mesh.point(a)), toEigen(mesh.point(b))) >
          kRoundoff * diagonal) {
        continue;
      }
      // Loops are numbered in order of their lowest halfedge index.
      std::vector<char> seen(mesh.n_halfedges(), 0);
      int loops = 0, loop = -1;
      std::size_t edges = 0;
      for (auto start : mesh.halfedges()) {
        if (!mesh.is_boundary(start) || seen[start.idx()]) continue;
        std::size_t count = 0;
        bool ours = false;
        auto g = start;
        do {
          seen[g.idx()] = 1;
          ours = ours || g == outside;
          ++count;
          g = mesh.next_halfedge_handle(g);
        } while (g != start);
        if (ours) {
          loop = loops;
          edges = count;
        }
        ++loops;
      }
      const auto near =
          (point - toEigen(mesh.point(a))).norm() <= (point - toEigen(mesh.point(b))).norm() ? a
                                                                                             : b;
      throw CanvasGrowError("origin", "the origin lies on a boundary of the mesh (boundary loop " +
                                          std::to_string(loop) + " of " + std::to_string(loops) +
                                          ", " + std::to_string(edges) + " edges, near vertex " +
                                          std::to_string(near.idx()) + " " +
                                          pointText(toEigen(mesh.point(near))) +
                                          "): pick an origin inside the surface");
    }
  }
}

// The painted faces edge-connected to `start`, in increasing order.
std::vector<int> floodFill(const TriMesh& mesh, int start, const std::vector<char>& painted) {
  std::vector<char> reached(mesh.n_faces(), 0);
  // Breadth first; the queue ends up holding every face reached.
  std::vector<int> queue{start};
  reached[start] = 1;
  for (std::size_t next = 0; next < queue.size(); ++next) {
    for (auto h : faceHalfedges(mesh, queue[next])) {
      const auto g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
      if (!g.is_valid() || reached[g.idx()] || !painted[g.idx()]) continue;
      reached[g.idx()] = 1;
      queue.push_back(g.idx());
    }
  }
  // Reading the marks in order costs less than sorting the queue.
  std::vector<int> region;
  region.reserve(queue.size());
  for (std::size_t f = 0; f < reached.size(); ++f)
    if (reached[f]) region.push_back(int(f));
  return region;
}

void rejectDegenerateFaces(const std::vector<Eigen::Vector3d>& p,
                           const std::vector<std::array<int, 3>>& corners,
                           const std::vector<int>& region, double diagonal) {
  std::size_t count = 0;
  int first = -1;
  for (int f : region) {
    const auto& [a, b, c] = corners[f];
    if ((p[b] - p[a]).cross(p[c] - p[a]).norm() <= 1e-12 * diagonal * diagonal) {
      if (count++ == 0) first = f;
    }
  }
  if (count > 0) {
    throw CanvasGrowError("mesh", "the painted region holds " + std::to_string(count) +
                                      " zero-area face(s), first face " + std::to_string(first) +
                                      ": repair the mesh or paint around them");
  }
}

// A vertex where the region's faces form more than one fan makes the boundary touch itself.
void rejectPinchedVertices(const TriMesh& mesh, const std::vector<int>& region) {
  std::vector<char> inRegion(mesh.n_faces(), 0);
  for (int f : region)
    inRegion[f] = 1;
  std::vector<int> borderOut(mesh.n_vertices(), 0);
  for (int f : region) {
    for (auto h : faceHalfedges(mesh, f)) {
      const auto g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
      if (g.is_valid() && inRegion[g.idx()]) continue;
      const auto v = mesh.from_vertex_handle(h);
      if (++borderOut[v.idx()] == 2) {
        throw CanvasGrowError("dabs", "the painted region touches itself only at vertex " +
                                          std::to_string(v.idx()) + " " +
                                          pointText(toEigen(mesh.point(v))) +
                                          ": paint over the gap there or away from it");
      }
    }
  }
}

struct Loop {
  std::vector<TriMesh::HalfedgeHandle> halfedges;
  double length = 0;
  bool meshHole = true;  // every edge is on a boundary of the source mesh
};

std::vector<Loop> boundaryLoops(const TriMesh& surface, const TriMesh& source,
                                const std::vector<int>& sourceVertex) {
  std::vector<Loop> loops;
  std::vector<char> seen(surface.n_halfedges(), 0);
  for (auto start : surface.halfedges()) {
    if (!surface.is_boundary(start) || seen[start.idx()]) continue;
    Loop loop;
    auto h = start;
    do {
      seen[h.idx()] = 1;
      loop.halfedges.push_back(h);
      const auto a = surface.from_vertex_handle(h);
      const auto b = surface.to_vertex_handle(h);
      loop.length += (surface.point(b) - surface.point(a)).norm();
      const auto sh = source.find_halfedge(TriMesh::VertexHandle(sourceVertex[a.idx()]),
                                           TriMesh::VertexHandle(sourceVertex[b.idx()]));
      loop.meshHole = loop.meshHole && sh.is_valid() && source.is_boundary(sh);
      h = surface.next_halfedge_handle(h);
    } while (h != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

Eigen::Vector3d loopCentroid(const TriMesh& surface, const Loop& loop) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto h : loop.halfedges)
    sum += toEigen(surface.point(surface.from_vertex_handle(h)));
  return sum / static_cast<double>(loop.halfedges.size());
}

// Section 3.1: the canvas boundary must be a single loop.
void requireOneLoop(const TriMesh& surface, const std::vector<Loop>& loops) {
  if (loops.empty()) {
    throw CanvasGrowError("dabs",
                          "the painting covers the whole closed surface around the origin (" +
                              std::to_string(surface.n_faces()) +
                              " faces), so the canvas has no boundary: leave part of the "
                              "surface unpainted");
  }
  if (loops.size() == 1) return;
  // The longest loop is taken as the outer one; the others are holes inside the canvas.
  std::size_t outer = 0;
  for (std::size_t i = 1; i < loops.size(); ++i)
    if (loops[i].length > loops[outer].length) outer = i;
  std::string islands, meshHoles;
  std::size_t islandCount = 0, meshHoleCount = 0;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (i == outer) continue;
    std::string& list = loops[i].meshHole ? meshHoles : islands;
    (loops[i].meshHole ? meshHoleCount : islandCount)++;
    if (!list.empty()) list += ", ";
    list += pointText(loopCentroid(surface, loops[i]));
  }
  const std::size_t holes = loops.size() - 1;
  std::string message = "the canvas boundary must be a single loop, but the painted region leaves ";
  message += std::to_string(holes);
  message += holes == 1 ? " hole" : " holes";
  message += " inside the canvas (" + std::to_string(loops.size()) + " boundary loops)";
  if (islandCount > 0) {
    message += "; unpainted parts near " + islands + ": paint over them";
  }
  if (meshHoleCount > 0) {
    message += "; holes of the mesh near " + meshHoles +
               ": paint so that the canvas does not "
               "enclose them";
  }
  throw CanvasGrowError("dabs", message);
}

}  // namespace

Canvas growCanvas(const MeshPtr& source, const CanvasGrowOptions& options) {
  checkInput(source, options);
  const TriMesh& mesh = source->surface;
  const std::vector<Eigen::Vector3d> p = points(mesh);
  const std::vector<std::array<int, 3>> corners = faceCorners(mesh);
  const double diagonal = boundingDiagonal(p);

  std::vector<char> paintedVertex(p.size(), 0);
  for (std::size_t v = 0; v < p.size(); ++v)
    paintedVertex[v] = insideSomeDab(p[v], options.dabs);
  std::vector<char> painted(corners.size(), 0);
  for (std::size_t f = 0; f < corners.size(); ++f) {
    painted[f] = std::all_of(corners[f].begin(), corners[f].end(),
                             [&](int v) { return paintedVertex[v] != 0; });
  }

  // Faces tied for nearest (the origin on a shared edge or vertex) prefer a painted one.
  auto closestOnFace = [&](std::size_t f) {
    const auto& [a, b, c] = corners[f];
    return closestPointOnTriangle(options.origin, p[a], p[b], p[c]);
  };
  std::vector<double> distance(corners.size());
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < corners.size(); ++f) {
    distance[f] = (closestOnFace(f) - options.origin).norm();
    nearest = std::min(nearest, distance[f]);
  }
  const double tolerance = options.originTolerance * diagonal;
  if (nearest > tolerance) {
    throw CanvasGrowError(
        "origin", "the origin " + pointText(options.origin) + " is " + numberText(nearest) +
                      " away from the surface, farther than the tolerance " +
                      numberText(tolerance) + " (" + numberText(100 * options.originTolerance) +
                      "% of the mesh's bounding-box diagonal): pick a point "
                      "on the surface");
  }
  std::vector<int> tied;
  for (std::size_t f = 0; f < corners.size(); ++f)
    if (distance[f] <= nearest + kRoundoff * diagonal) tied.push_back(int(f));
  const auto paintedTie =
      std::find_if(tied.begin(), tied.end(), [&](int f) { return painted[f] != 0; });
  const int originFace = paintedTie != tied.end() ? *paintedTie : tied.front();
  const Eigen::Vector3d originPoint = closestOnFace(std::size_t(originFace));

  rejectOriginOnBoundary(mesh, tied, originPoint, diagonal);
  if (!insideSomeDab(originPoint, options.dabs)) {
    throw CanvasGrowError("origin", "the origin " + pointText(originPoint) +
                                        " is outside every dab: paint over the origin or move it "
                                        "into the painted region");
  }
  if (!painted[originFace]) {
    throw CanvasGrowError("dabs", "the face under the origin (face " + std::to_string(originFace) +
                                      ") is not wholly painted: paint a larger dab there");
  }

  const std::vector<int> region = floodFill(mesh, originFace, painted);
  rejectDegenerateFaces(p, corners, region, diagonal);
  rejectPinchedVertices(mesh, region);

  Canvas canvas;
  canvas.source = source;
  Submesh sub = extractSubmesh(mesh, region);
  // Pinched vertices are rejected above, so a manifold source gives a manifold canvas.
  if (sub.unattachedFace >= 0) {
    throw CanvasGrowError("mesh", "face " + std::to_string(sub.unattachedFace) +
                                      " of the painted region cannot be attached to its "
                                      "neighbours: the mesh is not manifold there");
  }
  canvas.surface = std::move(sub.surface);
  canvas.sourceVertex = std::move(sub.sourceVertex);
  canvas.sourceFace = std::move(sub.sourceFace);
  canvas.originFace =
      int(std::lower_bound(region.begin(), region.end(), originFace) - region.begin());

  const std::vector<Loop> loops = boundaryLoops(canvas.surface, mesh, canvas.sourceVertex);
  requireOneLoop(canvas.surface, loops);
  setBoundaryAndOrigin(canvas, canvas.originFace, originPoint);
  return canvas;
}

}  // namespace geobrush
