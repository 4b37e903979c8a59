#include "geobrush/projective_map.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "geobrush/exponential_map.hpp"
#include "geobrush/face_selection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

void checkCanvas(const Canvas& canvas) {
  const TriMesh& s = canvas.surface;
  if (s.n_faces() == 0) throw ProjectiveMapError("canvas", "the canvas has no faces");
  if (canvas.originFace < 0 || canvas.originFace >= int(s.n_faces())) {
    throw ProjectiveMapError(
        "canvas",
        "the canvas origin face " + std::to_string(canvas.originFace) + " is not on the canvas");
  }
  if (!canvas.originPoint.allFinite()) {
    throw ProjectiveMapError("canvas", "the canvas origin point is not finite");
  }
  const bool mapped = canvas.source && canvas.sourceVertex.size() == s.n_vertices() &&
                      canvas.sourceFace.size() == s.n_faces();
  if (canvas.source && !mapped) {
    throw ProjectiveMapError("canvas", "the canvas's source maps do not match its surface");
  }
  for (auto v : s.vertices()) {
    if (!pointOf(s, v).allFinite()) {
      throw ProjectiveMapError("canvas",
                               "canvas vertex " + std::to_string(v.idx()) + " is not finite");
    }
  }
}

void checkOptions(const ProjectiveMapOptions& o) {
  if (!o.view.allFinite()) throw ProjectiveMapError("view", "must be a finite vector");
  if (!std::isfinite(o.angleDegrees)) throw ProjectiveMapError("angle", "must be a finite number");
  if (o.reversedRing < 0) throw ProjectiveMapError("reversed_ring", "must be 0 or more");
}

// The canvas' vector area, the sum of its faces' area-weighted normals (the direction along which
// its projection has the largest area, set by its outline alone), and its total area.
struct CanvasAreas {
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
  double total = 0;
};
CanvasAreas areasOf(const TriMesh& mesh) {
  CanvasAreas areas;
  for (auto f : mesh.faces()) {
    auto v = mesh.cfv_begin(f);
    const Eigen::Vector3d a = pointOf(mesh, *v), b = pointOf(mesh, *++v), c = pointOf(mesh, *++v);
    const Eigen::Vector3d face = (b - a).cross(c - a) / 2;
    areas.vector += face;
    areas.total += face.norm();
  }
  return areas;
}

// n_P: the given view; by default the view under which the canvas shows its largest area (its
// vector area's direction) [ours], which a peak or a rough spot at the origin does not tilt; where
// the canvas has no such direction (it nearly closes), the source surface normal at the canvas
// origin (the whole one-ring of the source mesh, so that a canvas cut through a vertex does not
// tilt it).
Eigen::Vector3d viewNormal(const Canvas& canvas, const Eigen::Vector3d& view) {
  if (!view.isZero()) return view.normalized();
  const CanvasAreas areas = areasOf(canvas.surface);
  if (areas.vector.norm() > 0.1 * areas.total) return areas.vector.normalized();
  const bool onSource = canvas.source != nullptr;
  const TriMesh& mesh = onSource ? canvas.source->surface : canvas.surface;
  const int face = onSource ? canvas.sourceFace[std::size_t(canvas.originFace)] : canvas.originFace;
  const Eigen::Vector3d n = surfaceNormalAt(mesh, face, canvas.originPoint);
  if (n.isZero()) {
    throw ProjectiveMapError("canvas",
                             "the surface under the canvas origin has no normal: give a view");
  }
  return n;
}

Eigen::Vector3d centre(const Canvas& canvas, bool atVertex) {
  if (!atVertex) return canvas.originPoint;
  int v = canvas.originVertex;
  if (v < 0 || v >= int(canvas.surface.n_vertices()))
    v = canvas.surface.cfv_begin(TriMesh::FaceHandle(canvas.originFace))->idx();
  return pointOf(canvas.surface, v);
}

// The largest radius around the centre that every outline vertex reaches.
double innerRadius(const Canvas& canvas, const std::vector<Eigen::Vector2d>& uv) {
  double radius = std::numeric_limits<double>::infinity();
  for (auto h : canvas.surface.halfedges())
    if (canvas.surface.is_boundary(h))
      radius = std::min(radius, uv[std::size_t(canvas.surface.from_vertex_handle(h).idx())].norm());
  return radius;
}

// The canvas faces whose corners project within `radius`, with what they enclose, edge-connected
// to the origin face and with pinches cut off; in increasing order.
std::vector<int> facesWithin(const Canvas& canvas, const std::vector<Eigen::Vector2d>& uv,
                             double radius) {
  const TriMesh& s = canvas.surface;
  std::vector<char> selected(s.n_faces(), 0);
  for (auto f : s.faces()) {
    bool within = true;
    for (auto v : s.fv_range(f))
      within = within && uv[std::size_t(v.idx())].norm() <= radius;
    selected[std::size_t(f.idx())] = within;
  }
  selected[std::size_t(canvas.originFace)] = 1;
  fillEnclosed(s, selected, -1);
  const std::vector<int> reached = connectedFaces(s, canvas.originFace, selected);
  std::vector<char> connected(s.n_faces(), 0);
  for (int f : reached)
    connected[std::size_t(f)] = 1;
  removePinches(s, connected, reached);
  if (!connected[std::size_t(canvas.originFace)]) {
    throw ProjectiveMapError("crop_to_disc", "the cropped canvas touches itself at its origin");
  }
  return connectedFaces(s, canvas.originFace, connected);
}

// The canvas cut down to the faces whose corners project within the inner radius.
CanvasPtr cropToDisc(const Canvas& canvas, const std::vector<Eigen::Vector2d>& uv) {
  const double radius = innerRadius(canvas, uv);
  if (!(radius > 0) || !std::isfinite(radius)) {
    throw ProjectiveMapError("crop_to_disc",
                             "the canvas outline passes through the centre (or the canvas has "
                             "no outline): there is no disc to crop to");
  }
  const std::vector<int> kept = facesWithin(canvas, uv, radius);
  // A canvas without a source mesh (a test's) becomes its own.
  const MeshPtr mesh = canvas.source ? canvas.source : std::make_shared<const Mesh>(canvas.surface);
  std::vector<int> meshFaces;
  for (int f : kept)
    meshFaces.push_back(canvas.source ? canvas.sourceFace[std::size_t(f)] : f);
  const int originFace = meshFaces[std::size_t(
      std::lower_bound(kept.begin(), kept.end(), canvas.originFace) - kept.begin())];
  std::sort(meshFaces.begin(), meshFaces.end());
  auto cropped = std::make_shared<Canvas>();
  try {
    *cropped = canvasOnFaces(mesh, meshFaces, originFace, canvas.originPoint);
  } catch (const std::invalid_argument& e) {
    throw ProjectiveMapError("crop_to_disc", e.what());
  }
  if (meshStats(cropped->surface).boundaryLoops != 1) {
    throw ProjectiveMapError("crop_to_disc", "the cropped canvas is not bounded by one loop");
  }
  return cropped;
}

}  // namespace

Frame viewFrame(const Eigen::Vector3d& point, const Eigen::Vector3d& view, double angleDegrees) {
  // A degenerate triangle makes originFrame take the normals' sum: the view itself.
  const Eigen::Vector3d n = view.normalized();
  return originFrame({point, point, point}, {n, n, n}, point, angleDegrees);
}

Eigen::Vector2d projectOntoPlane(const Frame& plane, const Eigen::Vector3d& x) {
  const Eigen::Vector3d d = x - plane.point;
  return {d.dot(plane.uAxis), d.dot(plane.vAxis)};
}

double offsetFromPlane(const Frame& plane, const Eigen::Vector3d& x) {
  return (x - plane.point).dot(plane.normal);
}

Eigen::Vector3d surfaceNormalAt(const TriMesh& mesh, int face, const Eigen::Vector3d& point) {
  std::array<Eigen::Vector3d, 3> corners, normals;
  int k = 0;
  for (auto v : mesh.fv_range(TriMesh::FaceHandle(face))) {
    corners[std::size_t(k)] = pointOf(mesh, v);
    const Eigen::Vector3d n = angleWeightedNormal(mesh, v);
    normals[std::size_t(k++)] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : n;
  }
  try {
    return originFrame(corners, normals, point, 0).normal;
  } catch (const DemError&) {
    return Eigen::Vector3d::Zero();
  }
}

std::vector<std::uint8_t> foldedFaces(const TriMesh& mesh, const Eigen::Vector3d& view, int rings) {
  std::vector<std::uint8_t> flags(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (auto v : mesh.fv_range(f))
      p[std::size_t(k++)] = pointOf(mesh, v);
    flags[std::size_t(f.idx())] = (p[1] - p[0]).cross(p[2] - p[0]).dot(view) <= 0;
  }
  return growFaceRing(mesh, std::move(flags), rings);
}

ProjectiveMapResult projectiveMap(const CanvasPtr& canvas, const ProjectiveMapOptions& options) {
  if (!canvas) throw ProjectiveMapError("canvas", "there is no canvas");
  checkCanvas(*canvas);
  checkOptions(options);
  ProjectiveMapResult result;
  const Eigen::Vector3d view = viewNormal(*canvas, options.view);
  result.origin = viewFrame(centre(*canvas, options.centerAtVertex), view, options.angleDegrees);
  result.canvas = canvas;
  auto project = [&] {
    const TriMesh& s = result.canvas->surface;
    result.uv.clear();
    result.offset.clear();
    for (auto v : s.vertices()) {
      result.uv.push_back(projectOntoPlane(result.origin, pointOf(s, v)));
      result.offset.push_back(offsetFromPlane(result.origin, pointOf(s, v)));
    }
  };
  project();
  if (options.cropToDisc) {
    result.canvas = cropToDisc(*canvas, result.uv);
    project();
  }
  result.reversedFaces = foldedFaces(result.canvas->surface, view, options.reversedRing);
  return result;
}

TexelCoordinates texelCoordinates(const std::vector<Eigen::Vector2d>& uv) {
  TexelCoordinates texels;
  for (const auto& u : uv) {
    if (!u.allFinite()) throw std::invalid_argument("texel coordinates: a uv is not finite");
    texels.radius = std::max(texels.radius, u.norm());
  }
  if (!(texels.radius > 0)) {
    throw std::invalid_argument("texel coordinates: the decal has no extent (every uv is 0)");
  }
  const double scale = std::sqrt(2.0) * texels.radius;
  texels.st.reserve(uv.size());
  for (const auto& u : uv)
    texels.st.push_back(u / scale + Eigen::Vector2d::Constant(0.5));
  return texels;
}

Eigen::Vector2d domainOfTexel(const Eigen::Vector2d& st, double radius) {
  return (st - Eigen::Vector2d::Constant(0.5)) * (std::sqrt(2.0) * radius);
}

Canvas canvasOnFaces(const MeshPtr& mesh, const std::vector<int>& faces, int originFace,
                     const Eigen::Vector3d& originPoint) {
  Submesh sub = extractSubmesh(mesh->surface, faces);
  if (sub.unattachedFace >= 0) {
    throw std::invalid_argument("face " + std::to_string(sub.unattachedFace) +
                                " cannot be attached to its neighbours: the mesh is not "
                                "manifold there");
  }
  Canvas canvas;
  canvas.source = mesh;
  canvas.surface = std::move(sub.surface);
  canvas.sourceVertex = std::move(sub.sourceVertex);
  canvas.sourceFace = std::move(sub.sourceFace);
  const auto at = std::lower_bound(faces.begin(), faces.end(), originFace);
  if (at == faces.end() || *at != originFace)
    throw std::invalid_argument("the origin face is not one of the canvas faces");
  setBoundaryAndOrigin(canvas, int(at - faces.begin()), originPoint);
  return canvas;
}

}  // namespace geobrush
