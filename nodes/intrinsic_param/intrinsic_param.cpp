#include "intrinsic_param.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>

#include "geobrush/cut_paste.hpp"
#include "geobrush/exponential_map.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// F's boundary loop must be the surface's only one.
void checkFeature(const Canvas& feature) {
  const TriMesh& surface = feature.surface;
  const std::size_t n = feature.boundary.size();
  if (n < 3) throw IntrinsicParamError("feature", "F has no boundary loop of 3 or more vertices");
  std::vector<char> onLoop(surface.n_vertices(), 0);
  for (int v : feature.boundary) {
    if (v < 0 || v >= int(surface.n_vertices()) || onLoop[v])
      throw IntrinsicParamError("feature", "F's boundary loop lists vertex " + std::to_string(v) +
                                               " twice or out of range");
    onLoop[v] = 1;
  }
  for (auto v : surface.vertices())
    if (surface.is_boundary(v) && !onLoop[v.idx()])
      throw IntrinsicParamError("feature", "F has a boundary vertex (" + std::to_string(v.idx()) +
                                               ") off its boundary loop: more than one loop");
}

// B's boundary loop through vertex 0, in the direction of its boundary halfedges.
std::vector<int> baseLoop(const TriMesh& base) {
  TriMesh::HalfedgeHandle start;
  for (auto h : base.voh_range(TriMesh::VertexHandle(0)))
    if (base.is_boundary(h)) start = h;
  if (!start.is_valid()) throw IntrinsicParamError("base", "vertex 0 of B is not on its boundary");
  std::vector<int> loop;
  for (auto h = start; loop.empty() || h != start; h = base.next_halfedge_handle(h)) {
    loop.push_back(base.from_vertex_handle(h).idx());
    if (loop.size() > base.n_halfedges())
      throw IntrinsicParamError("base", "B's boundary loop never closes");
  }
  std::size_t boundaryHalfedges = 0;
  for (auto h : base.halfedges())
    boundaryHalfedges += base.is_boundary(h) ? 1 : 0;
  if (boundaryHalfedges != loop.size())
    throw IntrinsicParamError("base", "B has more than one boundary loop");
  return loop;
}

double cotangentAt(const Vector3d& p, const Vector3d& q, const Vector3d& r) {
  const Vector3d a = q - p, b = r - p;
  const double sine = a.cross(b).norm();
  if (!(sine > 1e-12 * a.norm() * b.norm())) return std::nan("");
  return a.dot(b) / sine;
}

std::vector<Vector2d> solveFree(const Eigen::SparseMatrix<double>& matrix,
                                const Eigen::MatrixX2d& rhs, const std::string& port) {
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> solver;
  solver.compute(matrix);
  if (solver.info() != Eigen::Success)
    throw IntrinsicParamError(
        port, "the intrinsic map's system is singular: " + solver.lastErrorMessage());
  const Eigen::MatrixX2d x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite())
    throw IntrinsicParamError(port, "the intrinsic map's system has no finite solution");
  std::vector<Vector2d> out(std::size_t(x.rows()));
  for (Eigen::Index r = 0; r < x.rows(); ++r)
    out[std::size_t(r)] = x.row(r).transpose();
  return out;
}

// The uv of B's boundary (originals at originalUv, split points interpolated by their share of
// the boundary's length between the originals around them), and B's interior solved.
std::vector<Vector2d> baseUvOver(const TriMesh& base, const std::vector<int>& loop,
                                 const std::vector<Vector2d>& originalUv,
                                 const IntrinsicParamOptions& options) {
  const int n = int(originalUv.size());
  std::vector<Vector2d> uv(base.n_vertices(), Vector2d::Zero());
  std::vector<char> fixed(base.n_vertices(), 0);
  const std::size_t m = loop.size();
  for (std::size_t k = 0; k < m;) {  // loop[k] is an original (the loop starts at vertex 0)
    const int from = loop[k];
    std::size_t next = k + 1;
    std::vector<double> along{0.0};
    for (; next < m && loop[next] >= n; ++next)
      along.push_back(along.back() +
                      (pointOf(base, loop[next]) - pointOf(base, loop[next - 1])).norm());
    const int to = loop[next % m];
    const double total = along.back() + (pointOf(base, to) - pointOf(base, loop[next - 1])).norm();
    for (std::size_t s = k; s < next; ++s) {
      const double t = total > 0 ? along[s - k] / total : 0.0;
      uv[loop[s]] = (1 - t) * originalUv[from] + t * originalUv[to];
      fixed[loop[s]] = 1;
    }
    k = next;
  }
  return solveIntrinsic(base, fixed, std::move(uv), options.lambda, options.mu, "base");
}

std::vector<Vector2d> featureUvOver(const Canvas& feature, const std::vector<Vector2d>& originalUv,
                                    const IntrinsicParamOptions& options) {
  std::vector<Vector2d> uv(feature.surface.n_vertices(), Vector2d::Zero());
  std::vector<char> fixed(feature.surface.n_vertices(), 0);
  for (std::size_t i = 0; i < feature.boundary.size(); ++i) {
    uv[feature.boundary[i]] = originalUv[i];
    fixed[feature.boundary[i]] = 1;
  }
  return solveIntrinsic(feature.surface, fixed, std::move(uv), options.lambda, options.mu,
                        "feature");
}

// The originals' uv under a boundary mode (not Auto).
std::vector<Vector2d> originalBoundaryUv(BoundaryMode mode, const TriMesh& base, int n,
                                         const PlaneFit& plane) {
  std::vector<Vector2d> planeUv(n);
  for (int i = 0; i < n; ++i)
    planeUv[i] = plane.project(pointOf(base, i));
  if (mode == BoundaryMode::Plane) return planeUv;
  int pinA = 0, pinB = 1;
  double farthest = -1;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      const double d = (pointOf(base, a) - pointOf(base, b)).squaredNorm();
      if (d > farthest) std::tie(farthest, pinA, pinB) = std::tuple(d, a, b);
    }
  const std::vector<Vector2d> free = leastSquaresConformalMap(base, pinA, pinB, "base");
  // Turned and moved onto the plane's projection, so that uv (0, 0) stays at its centroid.
  const Eigen::Matrix3d rigid =
      fitSimilarity2d(std::vector<Vector2d>(free.begin(), free.begin() + n),
                      std::vector<Vector2d>(planeUv.begin(), planeUv.begin() + n), false);
  std::vector<Vector2d> natural(n);
  for (int i = 0; i < n; ++i)
    natural[i] = rigid.topLeftCorner<2, 2>() * free[i] + rigid.topRightCorner<2, 1>();
  return mode == BoundaryMode::Natural ? natural : placeOnConvexHull(natural);
}

int countOutside(const Canvas& feature, const std::vector<Vector2d>& featureUv,
                 const std::vector<int>& loop, const std::vector<Vector2d>& baseUv) {
  std::vector<Vector2d> polygon;
  Eigen::AlignedBox2d box;
  for (int v : loop) {
    polygon.push_back(baseUv[v]);
    box.extend(baseUv[v]);
  }
  const double tolerance = 1e-9 * box.diagonal().norm();
  int outside = 0;
  for (auto v : feature.surface.vertices())
    if (!feature.surface.is_boundary(v) && !insidePolygon(polygon, featureUv[v.idx()], tolerance))
      ++outside;
  return outside;
}

// Whether the base's outline in the domain is a simple polygon (the walk on the target needs one).
bool simpleOutline(const std::vector<int>& loop, const std::vector<Vector2d>& baseUv) {
  std::vector<Vector2d> polygon;
  for (int v : loop)
    polygon.push_back(baseUv[v]);
  return firstSelfCrossing(polygon).first < 0;
}

// Faces clockwise beyond rounding (a face the convex hull lays flat is degenerate, not turned).
std::vector<std::uint8_t> clockwiseFaces(const TriMesh& mesh, const std::vector<Vector2d>& uv) {
  Eigen::AlignedBox2d box;
  for (const auto& p : uv)
    box.extend(p);
  const double rounding = 1e-12 * box.diagonal().squaredNorm();
  std::vector<std::uint8_t> flipped(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    std::array<Vector2d, 3> c;
    int k = 0;
    for (auto v : mesh.fv_range(f))
      c[k++] = uv[v.idx()];
    const Vector2d a = c[1] - c[0], b = c[2] - c[0];
    flipped[f.idx()] = a.x() * b.y() - a.y() * b.x() < -rounding ? 1 : 0;
  }
  return flipped;
}

Vector3d unitOr(const Vector3d& n, const Vector3d& fallback) {
  return n.norm() > 0 ? Vector3d(n.normalized()) : fallback;
}

void setNormals(const Canvas& feature, const TriMesh& base, IntrinsicParamResult& result) {
  const Vector3d fallback = result.plane.normal;
  result.featureNormal.resize(feature.surface.n_vertices());
  for (auto v : feature.surface.vertices()) {
    const bool onSource = feature.source && v.idx() < int(feature.sourceVertex.size());
    const Vector3d n =
        onSource ? angleWeightedNormal(feature.source->surface,
                                       TriMesh::VertexHandle(feature.sourceVertex[v.idx()]))
                 : angleWeightedNormal(feature.surface, v);
    result.featureNormal[v.idx()] = unitOr(n, fallback);
  }
  result.baseNormal = vertexNormals(base);
  for (auto& n : result.baseNormal)
    n = unitOr(n, fallback);
}

void alignToFrame(const Canvas& feature, const Parameterization& frame,
                  IntrinsicParamResult& result) {
  const Eigen::Matrix3d map = frameAlignment(feature, result.featureUv, frame);
  for (auto* uvs : {&result.featureUv, &result.baseUv})
    for (auto& p : *uvs)
      p = map.topLeftCorner<2, 2>() * p + map.topRightCorner<2, 1>();
  result.origin = frame.origin;
  result.rotation = frame.rotation;
  result.scale = frame.scale;
}

}  // namespace

std::vector<int> checkBaseConvention(const Canvas& feature, const TriMesh& base) {
  checkFeature(feature);
  const int n = int(feature.boundary.size());
  if (int(base.n_vertices()) < n)
    throw IntrinsicParamError("base", "B has " + std::to_string(base.n_vertices()) +
                                          " vertices, fewer than F's " + std::to_string(n) +
                                          " boundary vertices");
  const double tolerance = 1e-9 * boundingDiagonal(feature.surface);
  for (int i = 0; i < n; ++i) {
    const double gap = (pointOf(base, i) - pointOf(feature.surface, feature.boundary[i])).norm();
    if (!(gap <= tolerance))
      throw IntrinsicParamError("base", "B's vertex " + std::to_string(i) +
                                            " is not at F's boundary vertex " + std::to_string(i) +
                                            " (" + std::to_string(gap) + " away)");
  }
  const std::vector<int> loop = baseLoop(base);
  int expected = 0;
  for (int v : loop) {
    if (v >= n) continue;
    if (v != expected)
      throw IntrinsicParamError("base", "B's boundary reaches vertex " + std::to_string(v) +
                                            " where F's loop has vertex " +
                                            std::to_string(expected) +
                                            ": B's faces must be oriented like F's");
    ++expected;
  }
  if (expected != n)
    throw IntrinsicParamError("base",
                              "B's vertex " + std::to_string(expected) + " is not on its boundary");
  return loop;
}

PlaneFit fitBoundaryPlane(const std::vector<Vector3d>& loop) {
  PlaneFit plane;
  for (const auto& p : loop)
    plane.centroid += p / double(loop.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Vector3d vectorArea = Vector3d::Zero();
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Vector3d d = loop[i] - plane.centroid;
    covariance += d * d.transpose();
    vectorArea += 0.5 * d.cross(loop[(i + 1) % loop.size()] - plane.centroid);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  plane.normal = eigen.eigenvectors().col(0).normalized();
  // Boundary halfedges run against the faces: their loop is clockwise about the faces' side.
  if (plane.normal.dot(vectorArea) > 0) plane.normal = -plane.normal;
  plane.uAxis = eigen.eigenvectors().col(2).normalized();
  plane.vAxis = plane.normal.cross(plane.uAxis);
  return plane;
}

std::vector<Vector2d> solveIntrinsic(const TriMesh& mesh, const std::vector<char>& fixed,
                                     std::vector<Vector2d> uv, double lambda, double mu,
                                     const std::string& port) {
  std::vector<int> row(mesh.n_vertices(), -1);
  int unknowns = 0;
  for (auto v : mesh.vertices()) {
    if (fixed[v.idx()]) continue;
    if (mesh.valence(v) == 0)
      throw IntrinsicParamError(port, "vertex " + std::to_string(v.idx()) + " has no face");
    row[v.idx()] = unknowns++;
  }
  if (unknowns == 0) return uv;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(unknowns, 2);
  const auto couple = [&](int i, int j, double w) {
    entries.emplace_back(row[i], row[i], w);
    if (row[j] >= 0)
      entries.emplace_back(row[i], row[j], -w);
    else
      rhs.row(row[i]) += w * uv[j].transpose();
  };
  for (auto f : mesh.faces()) {
    std::array<int, 3> c;
    std::array<Vector3d, 3> x;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      c[k] = v.idx();
      x[k++] = pointOf(mesh, v.idx());
    }
    std::array<double, 3> cot;
    for (k = 0; k < 3; ++k)
      cot[k] = cotangentAt(x[k], x[(k + 1) % 3], x[(k + 2) % 3]);
    if (!std::isfinite(cot[0] + cot[1] + cot[2]))
      throw IntrinsicParamError(port, "face " + std::to_string(f.idx()) + " is degenerate");
    for (k = 0; k < 3; ++k) {
      if (row[c[k]] < 0) continue;
      const int j = (k + 1) % 3, l = (k + 2) % 3;
      couple(c[k], c[j], lambda * cot[l] + mu * cot[j] / (x[k] - x[j]).squaredNorm());
      couple(c[k], c[l], lambda * cot[j] + mu * cot[l] / (x[k] - x[l]).squaredNorm());
    }
  }
  Eigen::SparseMatrix<double> matrix(unknowns, unknowns);
  matrix.setFromTriplets(entries.begin(), entries.end());
  const std::vector<Vector2d> solved = solveFree(matrix, rhs, port);
  for (auto v : mesh.vertices())
    if (row[v.idx()] >= 0) uv[v.idx()] = solved[row[v.idx()]];
  return uv;
}

IntrinsicParamResult intrinsicParameterize(const Canvas& feature, const TriMesh& base,
                                           const IntrinsicParamOptions& options) {
  const std::vector<int> loop = checkBaseConvention(feature, base);
  const int n = int(feature.boundary.size());
  std::vector<Vector3d> originals(n);
  for (int i = 0; i < n; ++i)
    originals[i] = pointOf(base, i);
  IntrinsicParamResult result;
  result.plane = fitBoundaryPlane(originals);
  const auto solveWith = [&](BoundaryMode mode) {
    const std::vector<Vector2d> boundaryUv = originalBoundaryUv(mode, base, n, result.plane);
    result.used = mode;
    result.baseUv = baseUvOver(base, loop, boundaryUv, options);
    result.featureUv = featureUvOver(feature, boundaryUv, options);
    result.outsideVertices = countOutside(feature, result.featureUv, loop, result.baseUv);
  };
  const bool automatic = options.boundary == BoundaryMode::Auto;
  solveWith(automatic ? BoundaryMode::Plane : options.boundary);
  if (automatic && (result.outsideVertices > 0 || !simpleOutline(loop, result.baseUv))) {
    result.planeOutsideVertices = result.outsideVertices;
    result.planeOutlineCrosses = !simpleOutline(loop, result.baseUv);
    solveWith(BoundaryMode::ConvexHull);
  }
  result.origin =
      Frame{result.plane.centroid, result.plane.normal, result.plane.uAxis, result.plane.vAxis};
  if (options.frame) alignToFrame(feature, *options.frame, result);
  setNormals(feature, base, result);
  result.featureFlipped = clockwiseFaces(feature.surface, result.featureUv);
  result.baseFlipped = clockwiseFaces(base, result.baseUv);
  return result;
}

}  // namespace geobrush
