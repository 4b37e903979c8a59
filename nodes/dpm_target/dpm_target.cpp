#include "dpm_target.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "geobrush/face_selection.hpp"
#include "geobrush/projective_map.hpp"
#include "geobrush/text.hpp"

namespace geobrush {
namespace {

// The largest |uv| of the source map, refusing an empty, non-finite or single-point one.
double sourceRadius(const std::vector<Eigen::Vector2d>& sourceUv) {
  if (sourceUv.empty()) throw ProjectiveStampError("source", "the source map has no vertices");
  double radius = 0;
  for (std::size_t i = 0; i < sourceUv.size(); ++i) {
    if (!sourceUv[i].allFinite()) {
      throw ProjectiveStampError(
          "source", "the source map of vertex " + std::to_string(i) + " is not finite");
    }
    radius = std::max(radius, sourceUv[i].norm());
  }
  if (!(radius > 0)) {
    throw ProjectiveStampError("source",
                               "the source map is a single point: its canvas has no extent");
  }
  return radius;
}

void checkOptions(const ProjectiveStampOptions& o) {
  if (!std::isfinite(o.scale) || o.scale <= 0) {
    throw ProjectiveStampError("scale",
                               "must be a finite number > 0 (target distance = scale x "
                               "domain distance), got " +
                                   numberText(o.scale));
  }
  if (!std::isfinite(o.margin) || o.margin < 0) {
    throw ProjectiveStampError("margin", "must be a finite number >= 0");
  }
  if (!std::isfinite(o.angleDegrees))
    throw ProjectiveStampError("angle", "must be a finite number");
  if (!o.origin.allFinite()) {
    throw ProjectiveStampError("origin", "every coordinate must be a finite number");
  }
  if (!o.view.allFinite()) throw ProjectiveStampError("view", "must be a finite vector");
  if (!std::isfinite(o.originTolerance) || o.originTolerance < 0) {
    throw ProjectiveStampError("origin", "the tolerance must be a finite number >= 0");
  }
}

MeshPtr checkedMesh(MeshPtr mesh) {
  if (!mesh || mesh->surface.n_faces() == 0) {
    throw ProjectiveStampError("mesh", "the target mesh has no faces");
  }
  for (auto v : mesh->surface.vertices())
    if (!pointOf(mesh->surface, v).allFinite()) {
      throw ProjectiveStampError("mesh", "vertex " + std::to_string(v.idx()) +
                                             " of the target has a non-finite coordinate");
    }
  return mesh;
}

// Whether the triangle comes within `radius` of the plane's origin (0, 0).
bool meetsDisc(const std::array<Eigen::Vector2d, 3>& t, double radius) {
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  const double c0 = cross(t[1] - t[0], -t[0]), c1 = cross(t[2] - t[1], -t[1]),
               c2 = cross(t[0] - t[2], -t[2]);
  if ((c0 >= 0 && c1 >= 0 && c2 >= 0) || (c0 <= 0 && c1 <= 0 && c2 <= 0)) return true;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& a = t[std::size_t(k)];
    const Eigen::Vector2d ab = t[std::size_t((k + 1) % 3)] - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0 ? std::clamp(-a.dot(ab) / len2, 0.0, 1.0) : 0.0;
    if ((a + s * ab).norm() <= radius) return true;
  }
  return false;
}

// The faces edge-connected to `originFace` through faces whose projection meets the disc, in
// increasing order, with pinched vertices cut off.
std::vector<int> discFaces(const TriMesh& mesh, const Frame& plane, int originFace, double radius) {
  auto meets = [&](TriMesh::FaceHandle f) {
    std::array<Eigen::Vector2d, 3> t;
    int k = 0;
    for (auto v : mesh.fv_range(f))
      t[std::size_t(k++)] = projectOntoPlane(plane, pointOf(mesh, v));
    return meetsDisc(t, radius);
  };
  std::vector<char> selected(mesh.n_faces(), 0), seen(mesh.n_faces(), 0);
  std::vector<int> queue{originFace};
  seen[std::size_t(originFace)] = selected[std::size_t(originFace)] = 1;
  for (std::size_t next = 0; next < queue.size(); ++next)
    for (auto g : mesh.ff_range(TriMesh::FaceHandle(queue[next]))) {
      if (seen[std::size_t(g.idx())]) continue;
      seen[std::size_t(g.idx())] = 1;
      if (!meets(g)) continue;
      selected[std::size_t(g.idx())] = 1;
      queue.push_back(g.idx());
    }
  removePinches(mesh, selected, queue);
  if (!selected[std::size_t(originFace)]) {
    throw ProjectiveStampError("origin",
                               "the stamp touches itself at the origin's face: move the "
                               "origin or use a smaller scale");
  }
  return connectedFaces(mesh, originFace, selected);
}

// The canvas' boundary loops as surface vertices, each in the direction of its halfedges.
std::vector<std::vector<int>> boundaryLoops(const TriMesh& surface) {
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(surface.n_halfedges(), 0);
  for (auto start : surface.halfedges()) {
    if (!surface.is_boundary(start) || seen[std::size_t(start.idx())]) continue;
    std::vector<int> loop;
    auto h = start;
    do {
      seen[std::size_t(h.idx())] = 1;
      loop.push_back(surface.from_vertex_handle(h).idx());
      h = surface.next_halfedge_handle(h);
    } while (h != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

double loopArea(const std::vector<int>& loop, const std::vector<Eigen::Vector2d>& uv) {
  double twice = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Eigen::Vector2d& a = uv[std::size_t(loop[i])];
    const Eigen::Vector2d& b = uv[std::size_t(loop[(i + 1) % loop.size()])];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return std::abs(twice) / 2;
}

// Whether the canvas edge from surface vertex a to b lies on the target mesh's boundary.
bool onMeshBoundary(const Canvas& canvas, int a, int b) {
  const TriMesh& mesh = canvas.source->surface;
  const auto h = mesh.find_halfedge(TriMesh::VertexHandle(canvas.sourceVertex[std::size_t(a)]),
                                    TriMesh::VertexHandle(canvas.sourceVertex[std::size_t(b)]));
  return h.is_valid() && mesh.is_boundary(mesh.edge_handle(h));
}

bool touchesMeshBoundary(const Canvas& canvas, const std::vector<int>& loop) {
  for (std::size_t i = 0; i < loop.size(); ++i)
    if (onMeshBoundary(canvas, loop[i], loop[(i + 1) % loop.size()])) return true;
  return false;
}

bool isMeshHole(const Canvas& canvas, const std::vector<int>& loop) {
  for (std::size_t i = 0; i < loop.size(); ++i)
    if (!onMeshBoundary(canvas, loop[i], loop[(i + 1) % loop.size()])) return false;
  return true;
}

// Section 3.1's single loop: sets the canvas boundary to the outer loop (the largest in uv),
// refusing what the options do not allow.
void setOuterLoop(Canvas& canvas, const std::vector<Eigen::Vector2d>& uv, bool keepHoles) {
  const std::vector<std::vector<int>> loops = boundaryLoops(canvas.surface);
  if (loops.empty()) {
    throw ProjectiveStampError("scale",
                               "the stamp covers a whole closed part of the target: use "
                               "a smaller scale or a smaller source canvas");
  }
  std::size_t outer = 0;
  for (std::size_t i = 1; i < loops.size(); ++i)
    if (loopArea(loops[i], uv) > loopArea(loops[outer], uv)) outer = i;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (i == outer || (keepHoles && isMeshHole(canvas, loops[i]))) continue;
    const Eigen::Vector3d near = pointOf(canvas.surface, loops[i].front());
    throw ProjectiveStampError(
        "mesh",
        "the stamp's disc holds a hole (a hole of the target mesh, or a fold under the "
        "view) near " +
            pointText(near) + ": move the origin, turn the view or use a smaller scale");
  }
  if (!keepHoles && touchesMeshBoundary(canvas, loops[outer])) {
    throw ProjectiveStampError("scale",
                               "the stamp runs off the target mesh at its boundary: move "
                               "the origin away from it or use a smaller scale");
  }
  const auto& loop = loops[outer];
  const auto first = std::min_element(loop.begin(), loop.end()) - loop.begin();
  canvas.boundary.assign(loop.begin() + first, loop.end());
  canvas.boundary.insert(canvas.boundary.end(), loop.begin(), loop.begin() + first);
}

}  // namespace

StampTarget::StampTarget(MeshPtr mesh)
    : mesh_(checkedMesh(std::move(mesh))),
      diagonal_(boundingDiagonal(mesh_->surface)),
      locator_(mesh_->surface) {}

ProjectiveStampResult projectiveStamp(const StampTarget& target,
                                      const std::vector<Eigen::Vector2d>& sourceUv,
                                      const ProjectiveStampOptions& options) {
  checkOptions(options);
  const double radius = (1 + options.margin) * sourceRadius(sourceUv);
  const TriMesh& mesh = target.mesh()->surface;
  const SurfacePoint snapped = target.nearest(options.origin);
  const double tolerance = options.originTolerance * target.diagonal();
  if (snapped.distance > tolerance) {
    throw ProjectiveStampError("origin", "the origin " + pointText(options.origin) + " is " +
                                             numberText(snapped.distance) +
                                             " away from the target surface, farther than the "
                                             "tolerance " +
                                             numberText(tolerance) +
                                             ": pick a point on the surface");
  }
  const Eigen::Vector3d view = options.view.isZero()
                                   ? surfaceNormalAt(mesh, snapped.face, snapped.point)
                                   : Eigen::Vector3d(options.view.normalized());
  if (view.isZero()) {
    throw ProjectiveStampError("origin",
                               "the target has no surface normal at the origin: give "
                               "a view");
  }
  ProjectiveStampResult result;
  result.origin = viewFrame(snapped.point, view, options.angleDegrees);
  result.radius = radius;
  const std::vector<int> faces =
      discFaces(mesh, result.origin, snapped.face, options.scale * radius);
  try {
    result.canvas = canvasOnFaces(target.mesh(), faces, snapped.face, snapped.point);
  } catch (const std::invalid_argument& e) {
    throw ProjectiveStampError("mesh", e.what());
  }
  const TriMesh& surface = result.canvas.surface;
  result.uv.reserve(surface.n_vertices());
  for (auto v : surface.vertices())
    result.uv.push_back(projectOntoPlane(result.origin, pointOf(surface, v)) / options.scale);
  setOuterLoop(result.canvas, result.uv, options.keepHoles);
  result.reversedFaces = foldedFaces(surface, view, 0);
  return result;
}

}  // namespace geobrush
