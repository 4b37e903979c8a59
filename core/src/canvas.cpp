#include "geobrush/canvas.hpp"

#include <limits>

#include "geobrush/node.hpp"

namespace geobrush {
namespace {

void hashVectors(Hasher& hasher, const auto& vectors) {
  hasher.u64(vectors.size());
  for (const auto& v : vectors)
    for (int i = 0; i < int(v.size()); ++i)
      hasher.f64(v[i]);
}

void hashInts(Hasher& hasher, const std::vector<int>& values) {
  hasher.span(std::span<const int>(values));
}

void hashFrame(Hasher& hasher, const Frame& frame) {
  for (const auto* v : {&frame.point, &frame.normal, &frame.uAxis, &frame.vAxis})
    for (int i = 0; i < 3; ++i)
      hasher.f64((*v)[i]);
}

template <typename Matrix>
void hashMatrix(Hasher& hasher, const Matrix& m) {
  hasher.u64(std::uint64_t(m.rows())).u64(std::uint64_t(m.cols()));
  for (Eigen::Index i = 0; i < m.size(); ++i)
    hasher.f64(m.data()[i]);
}

void hashTriMesh(Hasher& hasher, const TriMesh& mesh) {
  hasher.u64(mesh.n_vertices());
  for (auto v : mesh.vertices())
    for (int i = 0; i < 3; ++i)
      hasher.f64(mesh.point(v)[i]);
  hasher.u64(mesh.n_faces());
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f))
      hasher.u64(std::uint64_t(v.idx()));
}

}  // namespace

void setBoundaryAndOrigin(Canvas& canvas, int originFace, const Eigen::Vector3d& originPoint) {
  const TriMesh& surface = canvas.surface;
  TriMesh::HalfedgeHandle start;
  for (auto h : surface.halfedges())
    if (surface.is_boundary(h) &&
        (!start.is_valid() ||
         surface.from_vertex_handle(h).idx() < surface.from_vertex_handle(start).idx()))
      start = h;
  canvas.boundary.clear();
  if (start.is_valid()) {
    auto h = start;
    do {
      canvas.boundary.push_back(surface.from_vertex_handle(h).idx());
      h = surface.next_halfedge_handle(h);
    } while (h != start && canvas.boundary.size() <= surface.n_halfedges());
  }
  canvas.originFace = originFace;
  canvas.originPoint = originPoint;
  canvas.originVertex = -1;
  double best = std::numeric_limits<double>::infinity();
  for (auto v : surface.fv_range(TriMesh::FaceHandle(originFace))) {
    const auto& p = surface.point(v);
    const double d = (Eigen::Vector3d(p[0], p[1], p[2]) - originPoint).norm();
    if (d < best || (d == best && v.idx() < canvas.originVertex)) {
      best = d;
      canvas.originVertex = v.idx();
    }
  }
}

Hash Canvas::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(source ? source->contentHash() : 0);
  hashTriMesh(hasher, surface);
  hashInts(hasher, sourceVertex);
  hashInts(hasher, sourceFace);
  hashInts(hasher, boundary);
  for (int i = 0; i < 3; ++i)
    hasher.f64(originPoint[i]);
  hasher.u64(std::uint64_t(originFace)).u64(std::uint64_t(originVertex));
  return hasher.digest();
}

std::string Canvas::summary() const {
  return "canvas: " + std::to_string(surface.n_vertices()) + " vertices, " +
         std::to_string(surface.n_faces()) + " faces, boundary of " +
         std::to_string(boundary.size());
}

Hash Parameterization::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(canvas ? canvas->contentHash() : 0);
  hashVectors(hasher, uv);
  hashVectors(hasher, normal);
  hashFrame(hasher, origin);
  hasher.f64(rotation).f64(scale);
  hasher.span(std::span<const std::uint8_t>(reversedFaces));
  return hasher.digest();
}

std::string Parameterization::summary() const {
  return "parameterization of " + std::to_string(uv.size()) + " vertices";
}

Hash Cage::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId);
  hashTriMesh(hasher, mesh);
  hashVectors(hasher, domain);
  hasher.u64(domainTriangles.size());
  for (const auto& t : domainTriangles)
    for (int i : t)
      hasher.u64(std::uint64_t(i));
  hashInts(hasher, top);
  hashInts(hasher, bottom);
  hasher.u64(frames.size());
  for (const auto& frame : frames)
    hashFrame(hasher, frame);
  return hasher.digest();
}

std::string Cage::summary() const {
  return "cage: " + std::to_string(mesh.n_vertices()) + " vertices, " +
         std::to_string(mesh.n_faces()) + " faces";
}

Hash GreenCoordinates::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(cage ? cage->contentHash() : 0);
  hashMatrix(hasher, phi);
  hashMatrix(hasher, psi);
  return hasher.digest();
}

std::string GreenCoordinates::summary() const {
  return "Green coordinates of " + std::to_string(phi.rows()) + " points";
}

MeshPtr zeroDraft(const Canvas& canvas) {
  TriMesh surface = canvas.surface;
  for (auto v : surface.vertices())
    surface.set_point(v, {0, 0, 0});
  return std::make_shared<const Mesh>(std::move(surface));
}

MeshPtr draftOrZero(Context& ctx) {
  if (ctx.hasInput("draft")) return ctx.in<Mesh>("draft");
  const auto source = ctx.in<Parameterization>("source");
  return ctx.derived("zero_draft", {"source"}, 0, [&] { return zeroDraft(*source->canvas); });
}

}  // namespace geobrush
