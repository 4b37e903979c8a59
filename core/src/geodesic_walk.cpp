#include "geobrush/geodesic_walk.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace geobrush {
namespace {

using Eigen::Vector3d;

// Twice the area below which a face counts as degenerate, relative to its longest edge squared.
constexpr double kDegenerateArea = 1e-14;

// A face's corners in the order of its halfedges, with what a step across it reads.
struct Triangle {
  int face = -1;
  std::array<TriMesh::HalfedgeHandle, 3> side;  // side[k] runs from corner k to corner k + 1
  std::array<int, 3> vertex{};
  std::array<Vector3d, 3> x;
  Vector3d normal = Vector3d::Zero();  // unit; zero for a degenerate face
  // The gradient of each barycentric coordinate: a unit step d changes coordinate k by
  // gradient[k] . d.
  std::array<Vector3d, 3> gradient;

  bool degenerate() const { return normal.isZero(); }
  int cornerOf(int v) const { return vertex[0] == v ? 0 : vertex[1] == v ? 1 : 2; }
  Vector3d position(const Vector3d& b) const { return b[0] * x[0] + b[1] * x[1] + b[2] * x[2]; }
};

Triangle triangleOf(const TriMesh& mesh, int face) {
  Triangle t;
  t.face = face;
  auto h = mesh.halfedge_handle(TriMesh::FaceHandle(face));
  for (int k = 0; k < 3; ++k) {
    t.side[k] = h;
    t.vertex[k] = mesh.from_vertex_handle(h).idx();
    t.x[k] = pointOf(mesh, mesh.from_vertex_handle(h));
    h = mesh.next_halfedge_handle(h);
  }
  const Vector3d cross = (t.x[1] - t.x[0]).cross(t.x[2] - t.x[0]);
  double longest = 0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, (t.x[(k + 1) % 3] - t.x[k]).squaredNorm());
  const double area2 = cross.norm();
  if (!(area2 > kDegenerateArea * longest) || !std::isfinite(area2)) return t;
  t.normal = cross / area2;
  for (int k = 0; k < 3; ++k)
    t.gradient[k] = t.normal.cross(t.x[(k + 2) % 3] - t.x[(k + 1) % 3]) / area2;
  return t;
}

Vector3d barycentricOf(const Triangle& t, const Vector3d& p) {
  Vector3d b;
  for (int k = 0; k < 3; ++k)
    b[k] = t.gradient[k].dot(p - t.x[(k + 1) % 3]);
  return b;
}

// Negative coordinates (rounding, or a point just outside) set to zero, the rest scaled to sum 1.
Vector3d clampBarycentric(Vector3d b) {
  b = b.cwiseMax(0.0);
  const double sum = b.sum();
  return sum > 0 ? Vector3d(b / sum) : Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
}

// The faces around an interior vertex, counter-clockwise from a given face: out[i] is the
// halfedge leaving the vertex in the i-th face, angle[i] that face's corner angle at the vertex.
struct Fan {
  std::vector<TriMesh::HalfedgeHandle> out;
  std::vector<double> angle;
  double total = 0;
};

// Empty when a face of the fan is degenerate.
Fan fanAround(const TriMesh& mesh, TriMesh::VertexHandle v, int firstFace) {
  Fan fan;
  TriMesh::HalfedgeHandle first;
  for (auto h : mesh.voh_range(v))
    if (mesh.face_handle(h).idx() == firstFace) first = h;
  auto h = first;
  const Vector3d centre = pointOf(mesh, v);
  do {
    const Vector3d a = pointOf(mesh, mesh.to_vertex_handle(h)) - centre;
    const auto back = mesh.prev_halfedge_handle(h);
    const Vector3d b = pointOf(mesh, mesh.from_vertex_handle(back)) - centre;
    const double sine = a.cross(b).norm();
    if (!(sine > kDegenerateArea * std::max(a.squaredNorm(), b.squaredNorm()))) return {};
    fan.out.push_back(h);
    fan.angle.push_back(std::atan2(sine, a.dot(b)));
    fan.total += fan.angle.back();
    h = mesh.opposite_halfedge_handle(back);
  } while (h != first && fan.out.size() <= mesh.valence(v));
  return fan;
}

// The unit vector along an edge leaving a vertex.
Vector3d edgeDirection(const TriMesh& mesh, TriMesh::HalfedgeHandle h) {
  return (pointOf(mesh, mesh.to_vertex_handle(h)) - pointOf(mesh, mesh.from_vertex_handle(h)))
      .normalized();
}

// The angle from `from` to `to` about `normal`, counter-clockwise seen from its tip.
double signedAngle(const Vector3d& from, const Vector3d& to, const Vector3d& normal) {
  return std::atan2(normal.dot(from.cross(to)), from.dot(to));
}

class Walker {
 public:
  Walker(const TriMesh& mesh, const GeodesicWalkOptions& options, double length)
      : mesh_(mesh),
        tolerance_(options.vertexTolerance),
        budget_(walkFaceBudget(mesh, length, options)),
        total_(length),
        remaining_(length) {}

  GeodesicWalkResult run(int face, const Vector3d& point, const Vector3d& direction);

 private:
  bool enter(int face, const Vector3d& barycentric, const Vector3d& direction, unsigned exits,
             const Vector3d& entry);
  bool step();
  int exitCorner(const Vector3d& rate, double& distance) const;
  bool crossSide(int corner);
  bool passVertex(int corner);
  bool depart(TriMesh::VertexHandle v, const Fan& fan, double position);
  bool stop(WalkStop why);

  const TriMesh& mesh_;
  double tolerance_;
  int budget_;
  double total_;
  double remaining_;
  Triangle tri_;
  Vector3d lambda_ = Vector3d::Zero();
  Vector3d dir_ = Vector3d::Zero();
  unsigned exits_ = 7;  // bit k: the walk may leave through the side opposite corner k
  GeodesicWalkResult result_;
};

// Starts on the face (from its vertex when the point is at one), then steps until done.
GeodesicWalkResult Walker::run(int face, const Vector3d& point, const Vector3d& direction) {
  tri_ = triangleOf(mesh_, face);
  if (tri_.degenerate()) {
    lambda_ = Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
    stop(WalkStop::Degenerate);
    return result_;
  }
  const Vector3d inPlane = direction - direction.dot(tri_.normal) * tri_.normal;
  if (!(inPlane.norm() > 1e-12 * direction.norm()))
    throw std::invalid_argument("the walk's direction is normal to its start face");
  const Vector3d b = clampBarycentric(barycentricOf(tri_, point));
  int corner = 0;
  b.maxCoeff(&corner);
  const auto v = TriMesh::VertexHandle(tri_.vertex[corner]);
  if (b[corner] < 1 - tolerance_ || mesh_.is_boundary(v)) {
    if (enter(face, b, inPlane.normalized(), 7, tri_.position(b)))
      while (step()) {
      }
    return result_;
  }
  // A start at a vertex: the direction's place among the vertex's total angle.
  lambda_ = Vector3d::Unit(corner);
  dir_ = inPlane.normalized();
  const Fan fan = fanAround(mesh_, v, face);
  if (fan.out.empty()) {
    stop(WalkStop::Degenerate);
    return result_;
  }
  double angle = signedAngle(edgeDirection(mesh_, fan.out[0]), dir_, tri_.normal);
  if (angle < 0) angle += 2 * std::numbers::pi;
  const double own = fan.angle[0];
  const double position =
      angle <= own ? angle : own + (angle - own) * (fan.total - own) / (2 * std::numbers::pi - own);
  if (depart(v, fan, position))
    while (step()) {
    }
  return result_;
}

bool Walker::enter(int face, const Vector3d& barycentric, const Vector3d& direction, unsigned exits,
                   const Vector3d& entry) {
  if (int(result_.faces.size()) >= budget_) return stop(WalkStop::FaceLimit);
  const Triangle next = triangleOf(mesh_, face);
  if (next.degenerate()) return stop(WalkStop::Degenerate);
  tri_ = next;
  lambda_ = barycentric;
  dir_ = (direction - direction.dot(tri_.normal) * tri_.normal).normalized();
  exits_ = exits;
  result_.faces.push_back(face);
  result_.points.push_back(entry);
  return true;
}

// The corner whose opposite side the ray leaves through first, and the distance to it; -1 when
// no allowed side lies ahead.
int Walker::exitCorner(const Vector3d& rate, double& distance) const {
  int corner = -1;
  distance = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (!((exits_ >> k) & 1u) || !(rate[k] < 0)) continue;
    const double t = std::max(lambda_[k], 0.0) / -rate[k];
    if (t < distance) {
      distance = t;
      corner = k;
    }
  }
  return corner;
}

// One straight piece inside the current face; false when the walk is over.
bool Walker::step() {
  Vector3d rate;
  for (int k = 0; k < 3; ++k)
    rate[k] = tri_.gradient[k].dot(dir_);
  double distance = 0;
  int corner = exitCorner(rate, distance);
  if (corner < 0 && (exits_ == 3 || exits_ == 5 || exits_ == 6)) {
    // Grazing entry: rounding turned the direction back across the side it came in by. It runs
    // along that side: remove the component across it.
    const int entry = exits_ == 6 ? 0 : exits_ == 5 ? 1 : 2;
    const Vector3d& g = tri_.gradient[entry];
    dir_ = (dir_ - dir_.dot(g) / g.squaredNorm() * g).normalized();
    for (int k = 0; k < 3; ++k)
      rate[k] = tri_.gradient[k].dot(dir_);
    corner = exitCorner(rate, distance);
  }
  if (corner < 0) return stop(WalkStop::Degenerate);
  if (distance >= remaining_) {
    lambda_ = clampBarycentric(lambda_ + remaining_ * rate);
    result_.length = total_;  // exactly, not the rounded sum of the pieces
    remaining_ = 0;
    return stop(WalkStop::Completed);
  }
  lambda_ += distance * rate;
  lambda_[corner] = 0;
  lambda_ = clampBarycentric(lambda_);
  remaining_ -= distance;
  result_.length += distance;
  int top = 0;
  lambda_.maxCoeff(&top);
  if (lambda_[top] >= 1 - tolerance_) return passVertex(top);
  return crossSide(corner);
}

// Unfolds across the side opposite `corner` (Polthier-Schmies Sec. 4): the direction keeps its
// angle to the side.
bool Walker::crossSide(int corner) {
  const int a = (corner + 1) % 3, b = (corner + 2) % 3;
  const auto across = mesh_.opposite_halfedge_handle(tri_.side[a]);
  if (mesh_.is_boundary(across)) return stop(WalkStop::Boundary);
  const int face = mesh_.face_handle(across).idx();
  const Triangle next = triangleOf(mesh_, face);
  if (next.degenerate()) return stop(WalkStop::Degenerate);
  const Vector3d e = (tri_.x[b] - tri_.x[a]).normalized();
  const Vector3d unfolded = dir_.dot(e) * e + dir_.dot(tri_.normal.cross(e)) * next.normal.cross(e);
  Vector3d lambda = Vector3d::Zero();
  lambda[next.cornerOf(tri_.vertex[a])] = lambda_[a];
  lambda[next.cornerOf(tri_.vertex[b])] = lambda_[b];
  int third = 0;
  while (next.vertex[third] == tri_.vertex[a] || next.vertex[third] == tri_.vertex[b])
    ++third;
  return enter(face, lambda, unfolded, 7 & ~(1u << third), tri_.position(lambda_));
}

// At a vertex: leave so that the angle on either side of the walk is half the total (the
// straightest continuation, Polthier-Schmies Def. 4).
bool Walker::passVertex(int corner) {
  const auto v = TriMesh::VertexHandle(tri_.vertex[corner]);
  lambda_ = Vector3d::Unit(corner);
  ++result_.vertices;
  if (mesh_.is_boundary(v)) return stop(WalkStop::Boundary);
  const Fan fan = fanAround(mesh_, v, tri_.face);
  if (fan.out.empty()) return stop(WalkStop::Degenerate);
  const double back = signedAngle(edgeDirection(mesh_, fan.out[0]), -dir_, tri_.normal);
  return depart(v, fan, std::clamp(back, 0.0, fan.angle[0]) + fan.total / 2);
}

// Leaves `v` at `position` radians counter-clockwise from the first edge of the fan.
bool Walker::depart(TriMesh::VertexHandle v, const Fan& fan, double position) {
  std::size_t i = 0;
  for (std::size_t turns = 0; position > fan.angle[i] && turns < 2 * fan.out.size(); ++turns) {
    position -= fan.angle[i];
    i = (i + 1) % fan.out.size();
  }
  const double psi = std::clamp(position, 0.0, fan.angle[i]);
  const int face = mesh_.face_handle(fan.out[i]).idx();
  const Triangle next = triangleOf(mesh_, face);
  if (next.degenerate()) return stop(WalkStop::Degenerate);
  const Vector3d e = edgeDirection(mesh_, fan.out[i]);
  const Vector3d direction = std::cos(psi) * e + std::sin(psi) * next.normal.cross(e);
  const int corner = next.cornerOf(v.idx());
  return enter(face, Vector3d::Unit(corner), direction, 1u << corner, pointOf(mesh_, v));
}

bool Walker::stop(WalkStop why) {
  if (result_.faces.empty()) {
    result_.faces.push_back(tri_.face);
    result_.points.push_back(tri_.position(lambda_));
  }
  result_.stop = why;
  result_.face = tri_.face;
  result_.point = tri_.position(lambda_);
  result_.direction = dir_;
  const auto f = TriMesh::FaceHandle(tri_.face);
  int i = 0;
  for (auto v : mesh_.fv_range(f))
    result_.barycentric[i++] = lambda_[tri_.cornerOf(v.idx())];
  result_.points.push_back(result_.point);
  return false;
}

}  // namespace

int walkFaceBudget(const TriMesh& mesh, double length, const GeodesicWalkOptions& options) {
  const double edge = options.meanEdge > 0 ? options.meanEdge : meanEdgeLength(mesh);
  const double crossings = edge > 0 ? 16 * std::ceil(length / edge) : 0;
  const double budget = double(mesh.n_faces()) + crossings + 16;
  return int(std::min(budget, double(std::max(options.maxFaces, 1))));
}

GeodesicWalkResult walkStraightest(const TriMesh& mesh, int face, const Eigen::Vector3d& point,
                                   const Eigen::Vector3d& direction, double length,
                                   const GeodesicWalkOptions& options) {
  if (face < 0 || face >= int(mesh.n_faces()))
    throw std::invalid_argument("the walk's start face " + std::to_string(face) +
                                " is not a face of the mesh");
  if (!point.allFinite() || !direction.allFinite())
    throw std::invalid_argument("the walk's start point and direction must be finite");
  if (!(length >= 0) || !std::isfinite(length))
    throw std::invalid_argument("the walk's length must be a finite number >= 0");
  Walker walker(mesh, options, length);
  return walker.run(face, point, direction);
}

Eigen::Vector3d rotateInFace(const TriMesh& mesh, int face, const Eigen::Vector3d& direction,
                             double angle) {
  const Vector3d n = faceUnitNormal(mesh, face);
  const Vector3d d = direction - direction.dot(n) * n;
  if (n.isZero() || !(d.norm() > 0)) return Vector3d::Zero();
  const Vector3d u = d.normalized();
  return std::cos(angle) * u + std::sin(angle) * n.cross(u);
}

Eigen::Vector3d faceUnitNormal(const TriMesh& mesh, int face) {
  return triangleOf(mesh, face).normal;
}

}  // namespace geobrush
