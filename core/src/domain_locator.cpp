#include "geobrush/domain_locator.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geobrush/node.hpp"

namespace geobrush {

using Eigen::Vector2d;
using Eigen::Vector3d;

Frame DomainHit::frame() const {
  Frame f;
  f.point = point;
  f.normal = normal;
  Vector3d u = jacobian.col(0) - jacobian.col(0).dot(normal) * normal;
  if (u.norm() < 1e-300) u = normal.unitOrthogonal();
  f.uAxis = u.normalized();
  f.vAxis = normal.cross(f.uAxis);
  return f;
}

DomainLocator::DomainLocator(const Parameterization& param) : param_(param) {
  if (!param.canvas || param.uv.size() != param.canvas->surface.n_vertices())
    throw std::invalid_argument("the parameterization does not match its canvas");
  const TriMesh& surface = param.canvas->surface;
  for (auto f : surface.faces()) {
    std::array<int, 3> ids;
    int k = 0;
    for (auto v : surface.fv_range(f))
      ids[k++] = v.idx();
    faces_.push_back(ids);
  }
  if (faces_.empty()) throw std::invalid_argument("the canvas has no faces");
  outlineEdges_.assign(faces_.size(), 0);
  bool hasOutline = false;
  for (auto h : surface.halfedges()) {
    if (!surface.is_boundary(h)) continue;
    // The boundary halfedge runs against its face's own halfedge on the same edge.
    const auto inner = surface.opposite_halfedge_handle(h);
    const int face = surface.face_handle(inner).idx();
    const int from = surface.from_vertex_handle(inner).idx();
    for (int k = 0; k < 3; ++k)
      if (faces_[std::size_t(face)][std::size_t(k)] == from)
        outlineEdges_[std::size_t(face)] |= std::uint8_t(1 << k);
    hasOutline = true;
  }
  if (!hasOutline) outlineEdges_.clear();
  Vector2d lo = param.uv.front(), hi = param.uv.front();
  for (const auto& p : param.uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // About one triangle per cell on average.
  const double area = std::max((hi - lo).prod(), 1e-300);
  step_ = std::max(std::sqrt(area / double(faces_.size())), 1e-12 * (hi - lo).maxCoeff() + 1e-300);
  corner_ = lo;
  cellsX_ = std::clamp(int((hi.x() - lo.x()) / step_) + 1, 1, 4096);
  cellsY_ = std::clamp(int((hi.y() - lo.y()) / step_) + 1, 1, 4096);
  step_ = std::max((hi.x() - lo.x()) / cellsX_, (hi.y() - lo.y()) / cellsY_) * (1 + 1e-12) + 1e-300;
  // The buckets as one array (counted, then filled in face order, so each bucket is ascending).
  std::vector<std::array<int, 4>> cellRanges(faces_.size());
  bucketStart_.assign(std::size_t(cellsX_) * cellsY_ + 1, 0);
  for (int f = 0; f < int(faces_.size()); ++f) {
    Vector2d a = param.uv[faces_[f][0]], b = a;
    for (int k = 1; k < 3; ++k) {
      a = a.cwiseMin(param.uv[faces_[f][k]]);
      b = b.cwiseMax(param.uv[faces_[f][k]]);
    }
    auto& r = cellRanges[std::size_t(f)];
    r[0] = std::clamp(int((a.x() - corner_.x()) / step_), 0, cellsX_ - 1);
    r[1] = std::clamp(int((b.x() - corner_.x()) / step_), 0, cellsX_ - 1);
    r[2] = std::clamp(int((a.y() - corner_.y()) / step_), 0, cellsY_ - 1);
    r[3] = std::clamp(int((b.y() - corner_.y()) / step_), 0, cellsY_ - 1);
    for (int j = r[2]; j <= r[3]; ++j)
      for (int i = r[0]; i <= r[1]; ++i)
        ++bucketStart_[std::size_t(j) * cellsX_ + i + 1];
  }
  for (std::size_t c = 1; c < bucketStart_.size(); ++c)
    bucketStart_[c] += bucketStart_[c - 1];
  bucketFaces_.resize(std::size_t(bucketStart_.back()));
  std::vector<int> fill(bucketStart_.begin(), bucketStart_.end() - 1);
  for (int f = 0; f < int(faces_.size()); ++f) {
    const auto& r = cellRanges[std::size_t(f)];
    for (int j = r[2]; j <= r[3]; ++j)
      for (int i = r[0]; i <= r[1]; ++i)
        bucketFaces_[std::size_t(fill[std::size_t(j) * cellsX_ + i]++)] = f;
  }
}

Vector3d DomainLocator::barycentricOf(int face, const Vector2d& u) const {
  const Vector2d& a = param_.uv[faces_[face][0]];
  const Vector2d e1 = param_.uv[faces_[face][1]] - a, e2 = param_.uv[faces_[face][2]] - a;
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  if (std::abs(det) < 1e-300) return Vector3d(1, 0, 0);  // degenerate in uv: its first corner
  const Vector2d d = u - a;
  const double s = (d.x() * e2.y() - d.y() * e2.x()) / det;
  const double t = (e1.x() * d.y() - e1.y() * d.x()) / det;
  return {1 - s - t, s, t};
}

DomainHit DomainLocator::hit(int face, const Vector3d& bary, bool inside) const {
  const TriMesh& surface = param_.canvas->surface;
  DomainHit h;
  h.face = face;
  h.barycentric = bary;
  h.inside = inside;
  Vector3d p[3];
  h.point.setZero();
  h.normal.setZero();
  for (int k = 0; k < 3; ++k) {
    const auto& q = surface.point(TriMesh::VertexHandle(faces_[face][k]));
    p[k] = {q[0], q[1], q[2]};
    h.point += bary[k] * p[k];
    h.normal += bary[k] * param_.normal[faces_[face][k]];
  }
  h.normal.normalize();
  // The affine map (u, v) -> point of the face: point = p0 + J (uv - uv0).
  const Vector2d& a = param_.uv[faces_[face][0]];
  Eigen::Matrix2d domain;
  domain.col(0) = param_.uv[faces_[face][1]] - a;
  domain.col(1) = param_.uv[faces_[face][2]] - a;
  Eigen::Matrix<double, 3, 2> edges;
  edges.col(0) = p[1] - p[0];
  edges.col(1) = p[2] - p[0];
  h.jacobian = std::abs(domain.determinant()) > 1e-300
                   ? Eigen::Matrix<double, 3, 2>(edges * domain.inverse())
                   : Eigen::Matrix<double, 3, 2>::Zero();
  return h;
}

std::span<const int> DomainLocator::bucket(int i, int j) const {
  const std::size_t cell = std::size_t(j) * std::size_t(cellsX_) + std::size_t(i);
  return {bucketFaces_.data() + bucketStart_[cell],
          std::size_t(bucketStart_[cell + 1] - bucketStart_[cell])};
}

DomainHit DomainLocator::locate(const Vector2d& u) const {
  // The cell of u in the unbounded grid, and its clamped version.
  const double ci = std::floor((u.x() - corner_.x()) / step_);
  const double cj = std::floor((u.y() - corner_.y()) / step_);
  const bool inGrid = ci >= 0 && cj >= 0 && ci < cellsX_ && cj < cellsY_;
  const auto reversed = [&](int f) {
    return !param_.reversedFaces.empty() && param_.reversedFaces[f] != 0;
  };
  if (inGrid) {
    int firstAny = -1;
    Vector3d firstAnyBary;
    for (int f : bucket(int(ci), int(cj))) {  // ascending face order
      const Vector3d b = barycentricOf(f, u);
      if (b.minCoeff() < -1e-12) continue;
      if (!reversed(f)) return hit(f, b, true);
      if (firstAny < 0) {
        firstAny = f;
        firstAnyBary = b;
      }
    }
    if (firstAny >= 0) return hit(firstAny, firstAnyBary, true);
  }
  return nearestOutside(u, ci, cj);
}

// Outside every triangle: the outline face whose boundary edge is closest to u, or without an
// outline the triangle whose clamped barycentric point is (ties: the lowest face index). Cells
// are searched in rings around u's cell; every point of a triangle first met in ring r is at least
// (r - 1) steps from u, so the search stops once that bound exceeds the best distance found.
DomainHit DomainLocator::nearestOutside(const Vector2d& u, double ci, double cj) const {
  const double limit = 2.0 * (cellsX_ + cellsY_);  // rings beyond reach no cell
  const long i0 = long(std::clamp(ci, -limit, limit));
  const long j0 = long(std::clamp(cj, -limit, limit));
  int best = -1;
  double bestDistance = std::numeric_limits<double>::infinity();
  auto consider = [&](long i, long j) {
    for (int f : bucket(int(i), int(j))) {
      double d = std::numeric_limits<double>::infinity();
      if (outlineEdges_.empty()) {
        Vector3d clamped = barycentricOf(f, u).cwiseMax(0.0);
        clamped /= clamped.sum();
        Vector2d q = Vector2d::Zero();
        for (int k = 0; k < 3; ++k)
          q += clamped[k] * param_.uv[faces_[f][k]];
        d = (q - u).squaredNorm();
      } else {
        for (int k = 0; k < 3; ++k) {
          if (!(outlineEdges_[std::size_t(f)] >> k & 1)) continue;
          const Vector2d& a = param_.uv[faces_[f][k]];
          const Vector2d edge = param_.uv[faces_[f][(k + 1) % 3]] - a;
          const double length = edge.squaredNorm();
          const double t = length > 0 ? std::clamp((u - a).dot(edge) / length, 0.0, 1.0) : 0.0;
          d = std::min(d, (a + t * edge - u).squaredNorm());
        }
        if (d == std::numeric_limits<double>::infinity()) continue;
      }
      if (d < bestDistance || (d == bestDistance && f < best)) {
        bestDistance = d;
        best = f;
      }
    }
  };
  // Ring r: rows j0 +- r and columns i0 +- r, each cut to the grid.
  auto row = [&](long j, long r) {
    if (j < 0 || j >= cellsY_) return;
    for (long i = std::max(i0 - r, 0L); i <= std::min(i0 + r, long(cellsX_) - 1); ++i)
      consider(i, j);
  };
  auto column = [&](long i, long r) {
    if (i < 0 || i >= cellsX_) return;
    for (long j = std::max(j0 - r + 1, 0L); j <= std::min(j0 + r - 1, long(cellsY_) - 1); ++j)
      consider(i, j);
  };
  const long rings = long(2 * limit) + 2;
  for (long r = 0; r <= rings; ++r) {
    const double bound = double(std::max(r - 1, 0L)) * step_;
    if (best >= 0 && bound * bound > bestDistance) break;
    row(j0 - r, r);
    if (r == 0) continue;
    row(j0 + r, r);
    column(i0 - r, r);
    column(i0 + r, r);
  }
  return hit(best, barycentricOf(best, u), false);
}

std::shared_ptr<const DomainLocator> derivedLocator(Context& ctx, std::string_view port) {
  const auto canvas = ctx.in<Parameterization>(port);
  return ctx.derived("domain_locator", {port}, 0,
                     [&] { return std::make_shared<const DomainLocator>(*canvas); });
}

}  // namespace geobrush
