#include "geobrush/cut_paste.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "geobrush/exponential_map.hpp"
#include "geobrush/hash.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

void hashVector3s(Hasher& hasher, const std::vector<Eigen::Vector3d>& values) {
  hasher.u64(values.size());
  for (const auto& v : values)
    hasher.f64(v.x()).f64(v.y()).f64(v.z());
}

Eigen::Vector3d interpolatedNormal(const std::array<Eigen::Vector3d, 3>& normals,
                                   const Eigen::Vector3d& b) {
  const Eigen::Vector3d n = b[0] * normals[0] + b[1] * normals[1] + b[2] * normals[2];
  const double length = n.norm();
  return length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::UnitZ();
}

Eigen::Vector3d basePoint(const std::array<Eigen::Vector3d, 3>& corners, const Eigen::Vector3d& b) {
  return b[0] * corners[0] + b[1] * corners[1] + b[2] * corners[2];
}

// The boundary loop through `start`'s outgoing boundary halfedge, as vertex ids.
std::vector<int> loopFrom(const TriMesh& mesh, TriMesh::HalfedgeHandle start) {
  std::vector<int> loop;
  auto h = start;
  do {
    loop.push_back(mesh.from_vertex_handle(h).idx());
    h = mesh.next_halfedge_handle(h);
    if (loop.size() > mesh.n_halfedges())
      throw std::invalid_argument("a boundary loop never closes");
  } while (h != start);
  return loop;
}

std::size_t boundaryLoopCount(const TriMesh& mesh) {
  std::vector<char> seen(mesh.n_halfedges(), 0);
  std::size_t loops = 0;
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || seen[h.idx()]) continue;
    ++loops;
    auto g = h;
    do {
      seen[g.idx()] = 1;
      g = mesh.next_halfedge_handle(g);
    } while (g != h);
  }
  return loops;
}

}  // namespace

Hash DetailEncoding::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId);
  hasher.u64(feature ? feature->contentHash() : 0).u64(base ? base->contentHash() : 0);
  hasher.u64(std::uint64_t(method));
  hasher.span(std::span<const int>(baseFace));
  hashVector3s(hasher, barycentric);
  hashVector3s(hasher, offset);
  hasher.u64(selfIntersections);
  return hasher.digest();
}

std::string DetailEncoding::summary() const {
  return std::string("detail encoding of ") + std::to_string(offset.size()) + " vertices (" +
         (method == DetailMethod::FaceFrame     ? "face frames"
          : method == DetailMethod::SmoothFrame ? "smooth frames"
                                                : "normal displacement") +
         ")";
}

Hash SurfacePath::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(mesh ? mesh->contentHash() : 0);
  hasher.span(std::span<const int>(face));
  hashVector3s(hasher, point);
  hasher.f64(closingGap).f64(scale);
  return hasher.digest();
}

std::string SurfacePath::summary() const {
  return "surface path of " + std::to_string(point.size()) + " points, closing gap " +
         std::to_string(closingGap);
}

FaceFrame faceFrame(const std::array<Eigen::Vector3d, 3>& corners) {
  FaceFrame frame;
  const Eigen::Vector3d edge = corners[1] - corners[0];
  const Eigen::Vector3d normal = edge.cross(corners[2] - corners[0]);
  if (edge.norm() == 0 || normal.norm() == 0) return frame;
  frame.e1 = edge.normalized();
  frame.n = normal.normalized();
  frame.e2 = frame.n.cross(frame.e1);
  return frame;
}

std::vector<Eigen::Vector3d> vertexNormals(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> normals(mesh.n_vertices(), Eigen::Vector3d::Zero());
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d n = angleWeightedNormal(mesh, v);
    if (n.norm() > 0) normals[v.idx()] = n.normalized();
  }
  return normals;
}

BaseFrameField baseFrameField(const TriMesh& base, const std::vector<Eigen::Vector2d>& uv) {
  BaseFrameField field;
  field.normal = vertexNormals(base);
  field.tangent.assign(base.n_vertices(), Eigen::Vector3d::Zero());
  for (auto f : base.faces()) {
    std::array<int, 3> c{};
    int k = 0;
    for (auto v : base.fv_range(f))
      c[std::size_t(k++)] = v.idx();
    Eigen::Matrix<double, 3, 2> edges;
    edges << toEigen(base.point(TriMesh::VertexHandle(c[1]))) -
                 toEigen(base.point(TriMesh::VertexHandle(c[0]))),
        toEigen(base.point(TriMesh::VertexHandle(c[2]))) -
            toEigen(base.point(TriMesh::VertexHandle(c[0])));
    Eigen::Matrix2d domain;
    domain << uv[std::size_t(c[1])] - uv[std::size_t(c[0])],
        uv[std::size_t(c[2])] - uv[std::size_t(c[0])];
    if (std::abs(domain.determinant()) == 0) continue;
    const Eigen::Vector3d du = (edges * domain.inverse()).col(0);
    const double area = 0.5 * edges.col(0).cross(edges.col(1)).norm();
    for (int v : c)
      field.tangent[std::size_t(v)] += area * du;
  }
  for (std::size_t v = 0; v < field.tangent.size(); ++v) {
    Eigen::Vector3d& t = field.tangent[v];
    t -= t.dot(field.normal[v]) * field.normal[v];
    if (t.norm() > 0) t.normalize();
  }
  return field;
}

BaseFace baseFace(const TriMesh& base, const BaseFrameField& field, int face) {
  BaseFace out;
  std::size_t k = 0;
  for (auto v : base.fv_range(TriMesh::FaceHandle(face))) {
    out.point[k] = toEigen(base.point(v));
    out.normal[k] = field.normal[std::size_t(v.idx())];
    out.tangent[k++] = field.tangent[std::size_t(v.idx())];
  }
  return out;
}

namespace {

FaceFrame smoothFrame(const BaseFace& face, const Eigen::Vector3d& b) {
  FaceFrame frame;
  frame.n = interpolatedNormal(face.normal, b);
  Eigen::Vector3d t = b[0] * face.tangent[0] + b[1] * face.tangent[1] + b[2] * face.tangent[2];
  t -= t.dot(frame.n) * frame.n;
  if (t.norm() == 0) return faceFrame(face.point);
  frame.e1 = t.normalized();
  frame.e2 = frame.n.cross(frame.e1);
  return frame;
}

}  // namespace

Eigen::Vector3d encodeOffset(const BaseFace& face, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& point, DetailMethod method) {
  const Eigen::Vector3d d = point - basePoint(face.point, b);
  if (method == DetailMethod::NormalDisplacement)
    return {0, 0, d.dot(interpolatedNormal(face.normal, b))};
  const FaceFrame frame =
      method == DetailMethod::SmoothFrame ? smoothFrame(face, b) : faceFrame(face.point);
  return {d.dot(frame.e1), d.dot(frame.e2), d.dot(frame.n)};
}

Eigen::Vector3d decodeOffset(const BaseFace& face, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& offset, DetailMethod method, double scale) {
  const Eigen::Vector3d base = basePoint(face.point, b);
  if (method == DetailMethod::NormalDisplacement)
    return base + scale * offset.z() * interpolatedNormal(face.normal, b);
  const FaceFrame frame =
      method == DetailMethod::SmoothFrame ? smoothFrame(face, b) : faceFrame(face.point);
  return base + scale * (offset.x() * frame.e1 + offset.y() * frame.e2 + offset.z() * frame.n);
}

Canvas canvasOfMesh(const MeshPtr& mesh) {
  const TriMesh& surface = mesh->surface;
  if (surface.n_vertices() == 0 || boundaryLoopCount(surface) != 1)
    throw std::invalid_argument("a base must be a disc: one boundary loop");
  const auto v0 = surface.vertex_handle(0);
  TriMesh::HalfedgeHandle start;
  for (auto h : surface.voh_range(v0))
    if (surface.is_boundary(h)) start = h;
  if (!start.is_valid()) throw std::invalid_argument("vertex 0 of a base must be on its boundary");
  Canvas canvas;
  canvas.source = mesh;
  canvas.surface = surface;
  canvas.sourceVertex.resize(surface.n_vertices());
  for (std::size_t v = 0; v < surface.n_vertices(); ++v)
    canvas.sourceVertex[v] = int(v);
  canvas.sourceFace.resize(surface.n_faces());
  for (std::size_t f = 0; f < surface.n_faces(); ++f)
    canvas.sourceFace[f] = int(f);
  canvas.boundary = loopFrom(surface, start);
  canvas.originVertex = 0;
  canvas.originPoint = toEigen(surface.point(v0));
  canvas.originFace = surface.face_handle(surface.opposite_halfedge_handle(start)).idx();
  return canvas;
}

Canvas canvasFromFaces(const MeshPtr& source, std::vector<int> faces, int originFace,
                       const Eigen::Vector3d& originPoint) {
  std::sort(faces.begin(), faces.end());
  const TriMesh& mesh = source->surface;
  std::vector<char> inRegion(mesh.n_faces(), 0);
  for (int f : faces)
    inRegion[f] = 1;
  std::vector<int> borderOut(mesh.n_vertices(), 0);
  for (int f : faces)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(f))) {
      const auto g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
      if (g.is_valid() && inRegion[g.idx()]) continue;
      const int v = mesh.from_vertex_handle(h).idx();
      if (++borderOut[v] == 2)
        throw std::invalid_argument("the region touches itself at vertex " + std::to_string(v));
    }
  Submesh sub = extractSubmesh(mesh, faces);
  if (sub.unattachedFace >= 0)
    throw std::invalid_argument("face " + std::to_string(sub.unattachedFace) +
                                " of the region is not manifold with its neighbours");
  const std::size_t loops = boundaryLoopCount(sub.surface);
  if (loops != 1)
    throw std::invalid_argument("the region is bounded by " + std::to_string(loops) +
                                " loops, not one");
  Canvas canvas;
  canvas.source = source;
  canvas.surface = std::move(sub.surface);
  canvas.sourceVertex = std::move(sub.sourceVertex);
  canvas.sourceFace = std::move(sub.sourceFace);
  const auto at = std::lower_bound(faces.begin(), faces.end(), originFace);
  if (at == faces.end() || *at != originFace)
    throw std::invalid_argument("the origin's face " + std::to_string(originFace) +
                                " is not in the region");
  setBoundaryAndOrigin(canvas, int(at - faces.begin()), originPoint);
  return canvas;
}

Eigen::Matrix3d fitSimilarity2d(const std::vector<Eigen::Vector2d>& from,
                                const std::vector<Eigen::Vector2d>& to, bool withScale) {
  if (from.size() != to.size() || from.empty())
    throw std::invalid_argument("a similarity needs as many points to map as to map onto");
  Eigen::Vector2d meanFrom = Eigen::Vector2d::Zero(), meanTo = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < from.size(); ++k) {
    meanFrom += from[k];
    meanTo += to[k];
  }
  meanFrom /= double(from.size());
  meanTo /= double(to.size());
  double re = 0, im = 0, spread = 0;
  for (std::size_t k = 0; k < from.size(); ++k) {
    const Eigen::Vector2d p = from[k] - meanFrom, q = to[k] - meanTo;
    re += p.x() * q.x() + p.y() * q.y();
    im += p.x() * q.y() - p.y() * q.x();
    spread += p.squaredNorm();
  }
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();
  const double size = withScale ? spread : std::hypot(re, im);
  if (spread > 0 && size > 0) linear << re / size, -im / size, im / size, re / size;
  Eigen::Matrix3d similarity = Eigen::Matrix3d::Identity();
  similarity.topLeftCorner<2, 2>() = linear;
  similarity.topRightCorner<2, 1>() = meanTo - linear * meanFrom;
  return similarity;
}

namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

bool segmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d) {
  const double o1 = cross2(b - a, c - a), o2 = cross2(b - a, d - a);
  const double o3 = cross2(d - c, a - c), o4 = cross2(d - c, b - c);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  auto on = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& x,
               double o) {
    return o == 0 && x.x() >= std::min(p.x(), q.x()) && x.x() <= std::max(p.x(), q.x()) &&
           x.y() >= std::min(p.y(), q.y()) && x.y() <= std::max(p.y(), q.y());
  };
  return on(a, b, c, o1) || on(a, b, d, o2) || on(c, d, a, o3) || on(c, d, b, o4);
}

}  // namespace

std::pair<int, int> firstSelfCrossing(const std::vector<Eigen::Vector2d>& p) {
  const int m = int(p.size());
  for (int i = 0; i < m; ++i)
    for (int j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;
      if (segmentsMeet(p[std::size_t(i)], p[std::size_t((i + 1) % m)], p[std::size_t(j)],
                       p[std::size_t((j + 1) % m)]))
        return {i, j};
    }
  return {-1, -1};
}

bool insidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p,
                   double tolerance) {
  int winding = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    const Eigen::Vector2d ab = b - a;
    const double t =
        ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    nearest = std::min(nearest, (a + t * ab - p).norm());
    const double side = cross2(ab, p - a);
    if (a.y() <= p.y() && b.y() > p.y() && side > 0) ++winding;
    if (a.y() > p.y() && b.y() <= p.y() && side < 0) --winding;
  }
  return winding != 0 || nearest <= tolerance;
}

void umbrellaSmoothToRest(TriMesh& mesh, const std::vector<char>& movable) {
  std::vector<int> unknown(mesh.n_vertices(), -1);
  int count = 0;
  for (auto v : mesh.vertices())
    if (movable[std::size_t(v.idx())] && mesh.valence(v) > 0)
      unknown[std::size_t(v.idx())] = count++;
  if (count == 0) return;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 3);
  for (auto v : mesh.vertices()) {
    const int row = unknown[std::size_t(v.idx())];
    if (row < 0) continue;
    entries.emplace_back(row, row, double(mesh.valence(v)));
    for (auto w : mesh.vv_range(v)) {
      const int column = unknown[std::size_t(w.idx())];
      if (column >= 0)
        entries.emplace_back(row, column, -1.0);
      else
        rhs.row(row) += toEigen(mesh.point(w)).transpose();
    }
  }
  Eigen::SparseMatrix<double> laplacian(count, count);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  if (solver.info() != Eigen::Success) return;  // a piece with no fixed vertex
  const Eigen::MatrixXd x = solver.solve(rhs);
  for (auto v : mesh.vertices())
    if (const int row = unknown[std::size_t(v.idx())]; row >= 0)
      mesh.set_point(v, TriMesh::Point(x(row, 0), x(row, 1), x(row, 2)));
}

void umbrellaSmooth(TriMesh& mesh, const std::vector<char>& movable, int iterations) {
  std::vector<TriMesh::Point> next(mesh.n_vertices());
  for (int it = 0; it < iterations; ++it) {
    for (auto v : mesh.vertices()) {
      next[v.idx()] = mesh.point(v);
      if (!movable[v.idx()]) continue;
      TriMesh::Point sum(0, 0, 0);
      int count = 0;
      for (auto w : mesh.vv_range(v)) {
        sum += mesh.point(w);
        ++count;
      }
      if (count > 0) next[v.idx()] = sum / double(count);
    }
    for (auto v : mesh.vertices())
      mesh.set_point(v, next[v.idx()]);
  }
}

}  // namespace geobrush
