#include "gc_warp.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <numbers>
#include <sstream>
#include <thread>
#include <utility>

namespace geobrush {
namespace {

constexpr double kInvFourPi = 1.0 / (4.0 * std::numbers::pi);
// Ratios beyond this would overflow a double before the log; the terms they would enter are
// multiplied by a distance below 1e-150 and vanish.
constexpr double kMaxLogRatio = 1e300;

Eigen::Vector3d toEigen(const TriMesh::Point& p) {
  return {p[0], p[1], p[2]};
}

std::vector<Eigen::Vector3d> cagePoints(const TriMesh& cage) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(cage.n_vertices());
  for (auto v : cage.vertices())
    points.push_back(toEigen(cage.point(v)));
  return points;
}

std::vector<std::array<int, 3>> cageFaces(const TriMesh& cage) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(cage.n_faces());
  for (auto f : cage.faces()) {
    std::array<int, 3> corners{};
    int k = 0;
    for (auto v : cage.fv_range(f))
      corners[std::size_t(k++)] = v.idx();
    faces.push_back(corners);
  }
  return faces;
}

double boundingDiagonal(const std::vector<Eigen::Vector3d>& points) {
  Eigen::AlignedBox3d box;
  for (const auto& p : points)
    box.extend(p);
  return box.isEmpty() ? 0.0 : box.diagonal().norm();
}

// A face's point-independent data. Corner k = a_k; edge k runs from a_k to a_{k+1} with unit
// direction t_k and in-plane outward normal m_k = t_k x n.
struct FaceGeometry {
  std::array<Eigen::Vector3d, 3> corner;
  Eigen::Vector3d normal;
  double twiceArea = 0;
  std::array<Eigen::Vector3d, 3> edgeDir;
  std::array<Eigen::Vector3d, 3> edgeNormal;
  std::array<double, 3> edgeLength{};
  // |grad Gamma_l| / (4 pi) = l_{l+1} / (2 A 4 pi): Gamma_l(p) = h_{l+1} |grad Gamma_l| at a foot
  // point p whose distance to the opposite edge's line is h_{l+1}.
  std::array<double, 3> hatWeight{};
  // m_k . m_e: the in-plane gradient of Gamma_l is -|grad Gamma_l| m_{l+1}.
  Eigen::Matrix3d edgeNormalGram;
};

FaceGeometry faceGeometry(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                          const Eigen::Vector3d& a2) {
  FaceGeometry g;
  g.corner = {a0, a1, a2};
  const Eigen::Vector3d cross = (a1 - a0).cross(a2 - a0);
  g.twiceArea = cross.norm();
  g.normal = cross / g.twiceArea;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d edge = g.corner[std::size_t((k + 1) % 3)] - g.corner[std::size_t(k)];
    g.edgeLength[std::size_t(k)] = edge.norm();
    g.edgeDir[std::size_t(k)] = edge / g.edgeLength[std::size_t(k)];
    g.edgeNormal[std::size_t(k)] = g.edgeDir[std::size_t(k)].cross(g.normal);
  }
  for (int l = 0; l < 3; ++l) {
    g.hatWeight[std::size_t(l)] = g.edgeLength[std::size_t((l + 1) % 3)] / g.twiceArea * kInvFourPi;
    for (int e = 0; e < 3; ++e)
      g.edgeNormalGram(l, e) = g.edgeNormal[std::size_t(l)].dot(g.edgeNormal[std::size_t(e)]);
  }
  return g;
}

// Integral of 1/|xi - eta| over the segment from a to b, where sa = t.(a - eta) with t the unit
// direction a -> b, ra = |a - eta|, rb = |b - eta| and r0sq the squared distance from eta to the
// segment's line. Each branch avoids the cancellation of R + s with s < 0 by (R + s)(R - s) = r0^2.
// The value is direction-independent. Where eta lies on the closed segment the integral
// diverges, but every term it enters is then multiplied by zero; 0 keeps those products finite.
double edgeLogIntegral(double sa, double length, double ra, double rb, double r0sq) {
  const double sb = sa + length;
  double num, den;
  if (sa >= 0) {
    num = rb + sb;
    den = ra + sa;
  } else if (sb <= 0) {
    num = ra - sa;
    den = rb - sb;
  } else {
    num = (rb + sb) * (ra - sa);
    den = r0sq;
  }
  return den * kMaxLogRatio > num ? std::log(num / den) : 0.0;
}

// The per-point sums, kept by one thread for one point at a time.
struct PointSums {
  explicit PointSums(std::size_t vertices) : phi(vertices, 0.0) {}
  std::vector<double> phi;
  double solidAngle = 0;  // of the faces not touching the point
  // Faces within epsilon of the point.
  struct Touching {
    int face;
    std::array<double, 3> hat;  // Gamma_l(p) / (4 pi)
    double d;
  };
  std::vector<Touching> touching;
};

// Adds one face's terms for the point eta (LLCO08 section 3, Green's third identity):
//   psi_j   = 1/(4 pi) int_t 1/r           = 1/(4 pi) (sum_e h_e L_e - d Omega),
//   phi_j,l = 1/(4 pi) int_t Gamma_l d/r^3 = 1/(4 pi) (Gamma_l(p) Omega - d sum_e (grad Gamma_l .
//   m_e) L_e),
// with d = n.(a_0 - eta) > 0 inside, p the foot of eta on the plane, h_e = m_e.(a_e - eta), Omega
// the signed solid angle (Van Oosterom and Strackee) and L_e the edge integrals of 1/r. Returns
// psi_j.
double addFace(const FaceGeometry& g, const std::array<int, 3>& vertices, int face,
               const Eigen::Vector3d& eta, const std::array<double, 3>& r,
               const std::array<double, 3>& logIntegral, double tolerance, PointSums& sums) {
  const Eigen::Vector3d v0 = g.corner[0] - eta;
  const Eigen::Vector3d v1 = g.corner[1] - eta;
  const Eigen::Vector3d v2 = g.corner[2] - eta;
  double d = g.normal.dot(v0);
  const std::array<double, 3> h = {g.edgeNormal[0].dot(v0), g.edgeNormal[1].dot(v1),
                                   g.edgeNormal[2].dot(v2)};
  const double hL = h[0] * logIntegral[0] + h[1] * logIntegral[1] + h[2] * logIntegral[2];
  const std::array<double, 3> hat = {h[1] * g.hatWeight[0], h[2] * g.hatWeight[1],
                                     h[0] * g.hatWeight[2]};
  const Eigen::Vector3d gramL =
      g.edgeNormalGram * Eigen::Vector3d(logIntegral[0], logIntegral[1], logIntegral[2]);
  for (int l = 0; l < 3; ++l)
    sums.phi[std::size_t(vertices[std::size_t(l)])] +=
        d * g.hatWeight[std::size_t(l)] * gramL[(l + 1) % 3];
  if (std::abs(d) <= tolerance) {
    // Within rounding of the plane the sign of d, and with it the solid angle (which jumps by
    // 4 pi across the face), is unreliable. A face touching the point gets its share of what
    // the other faces leave of 4 pi (its interior limit); one beside the point subtends ~0.
    if (std::min({h[0], h[1], h[2]}) >= -tolerance) sums.touching.push_back({face, hat, d});
    return hL * kInvFourPi;
  }
  const double den = r[0] * r[1] * r[2] + v0.dot(v1) * r[2] + v0.dot(v2) * r[1] + v1.dot(v2) * r[0];
  const double omega = 2.0 * std::atan2(g.twiceArea * d, den);
  sums.solidAngle += omega;
  for (int l = 0; l < 3; ++l)
    sums.phi[std::size_t(vertices[std::size_t(l)])] += hat[std::size_t(l)] * omega;
  return (hL - d * omega) * kInvFourPi;
}

// Distributes the solid angle left to the faces touching the point, writes its phi row and
// resets the sums; psi already holds the row's face terms. Returns whether the point lies inside
// (total solid angle 4 pi, not 0).
bool finishPoint(PointSums& sums, const std::vector<std::array<int, 3>>& faces, Eigen::Index row,
                 Eigen::MatrixXd& phi, Eigen::MatrixXd& psi) {
  const double fourPi = 4.0 * std::numbers::pi;
  bool inside = std::abs(sums.solidAngle - fourPi) < 2.0 * std::numbers::pi;
  if (!sums.touching.empty()) {
    const double share = (fourPi - sums.solidAngle) / double(sums.touching.size());
    for (const auto& [face, hat, d] : sums.touching) {
      for (int l = 0; l < 3; ++l)
        sums.phi[std::size_t(faces[std::size_t(face)][std::size_t(l)])] +=
            hat[std::size_t(l)] * share;
      psi(row, face) -= d * share * kInvFourPi;
    }
    inside = true;
    sums.touching.clear();
  }
  for (std::size_t i = 0; i < sums.phi.size(); ++i) {
    phi(row, Eigen::Index(i)) = sums.phi[i];
    sums.phi[i] = 0;
  }
  sums.solidAngle = 0;
  return inside;
}

// Runs body(first, last) over fixed blocks of [0, count) on `threads` threads. Each block's
// output depends only on its own indices, so the result does not depend on the thread count.
template <typename Body>
void parallelBlocks(std::size_t count, int threads, Body body) {
  constexpr std::size_t kBlock = 64;
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  auto work = [&] {
    try {
      for (std::size_t b = next++; b < blocks; b = next++)
        body(b * kBlock, std::min(count, (b + 1) * kBlock));
    } catch (...) {
      const std::lock_guard lock(failureMutex);
      if (!failure) failure = std::current_exception();
      next = blocks;
    }
  };
  const int n = int(std::min<std::size_t>(std::size_t(std::max(threads, 1)), blocks));
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t)
    pool.emplace_back(work);
  work();
  for (auto& t : pool)
    t.join();
  if (failure) std::rethrow_exception(failure);
}

std::string faceText(int face) {
  std::string text = "face ";
  text += std::to_string(face);
  return text;
}

}  // namespace

void checkCage(const TriMesh& cage) {
  if (cage.n_faces() < 4) throw CageError("the cage needs at least 4 faces to be closed");
  for (auto v : cage.vertices()) {
    std::string where = "vertex ";
    where += std::to_string(v.idx());
    if (!toEigen(cage.point(v)).allFinite())
      throw CageError(where + " of the cage has a non-finite coordinate");
    if (cage.is_isolated(v)) throw CageError(where + " of the cage belongs to no face");
    if (!cage.is_manifold(v)) throw CageError(where + " of the cage is not manifold");
  }
  for (auto h : cage.halfedges())
    if (cage.is_boundary(h)) {
      std::string message = "the cage is not closed: edge ";
      message += std::to_string(cage.edge_handle(h).idx());
      message += " has one face";
      throw CageError(message);
    }
  const auto points = cagePoints(cage);
  const double scale = boundingDiagonal(points);
  const auto faces = cageFaces(cage);
  double volume = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& a = points[std::size_t(faces[f][0])];
    const auto& b = points[std::size_t(faces[f][1])];
    const auto& c = points[std::size_t(faces[f][2])];
    if ((b - a).cross(c - a).norm() <= 1e-14 * scale * scale)
      throw CageError(faceText(int(f)) + " of the cage is degenerate (zero area)");
    volume += a.dot(b.cross(c)) / 6.0;
  }
  if (!(volume > 0)) {
    std::ostringstream message;
    message << "the cage is oriented inward (signed volume " << volume
            << " <= 0): its faces must be wound counter-clockwise seen from outside";
    throw CageError(message.str());
  }
}

GreenCoordinatesResult computeGreenCoordinates(const TriMesh& cage,
                                               const std::vector<Eigen::Vector3d>& points,
                                               const GreenOptions& options) {
  checkCage(cage);
  const auto vertices = cagePoints(cage);
  const auto faces = cageFaces(cage);
  const double tolerance = options.epsilon * boundingDiagonal(vertices);

  // Every edge's integral of 1/r serves both its faces: computed once per point.
  struct Edge {
    int a, b;
    Eigen::Vector3d dir;
    double length;
  };
  std::vector<Edge> edges;
  std::vector<std::array<int, 3>> faceEdges(faces.size());
  std::map<std::pair<int, int>, int> edgeIndex;
  std::vector<FaceGeometry> geometry;
  geometry.reserve(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& c = faces[f];
    geometry.push_back(faceGeometry(vertices[std::size_t(c[0])], vertices[std::size_t(c[1])],
                                    vertices[std::size_t(c[2])]));
    for (int k = 0; k < 3; ++k) {
      const auto key = std::minmax(c[std::size_t(k)], c[std::size_t((k + 1) % 3)]);
      auto [it, added] = edgeIndex.try_emplace({key.first, key.second}, int(edges.size()));
      if (added) {
        const Eigen::Vector3d e =
            vertices[std::size_t(key.second)] - vertices[std::size_t(key.first)];
        edges.push_back({key.first, key.second, e.normalized(), e.norm()});
      }
      faceEdges[f][std::size_t(k)] = it->second;
    }
  }

  GreenCoordinatesResult result;
  const auto n = Eigen::Index(points.size());
  result.phi.resize(n, Eigen::Index(vertices.size()));
  result.psi.resize(n, Eigen::Index(faces.size()));
  std::vector<char> inside(points.size(), 1);
  const int threads = options.threads > 0 ? options.threads
                                          : int(std::max(1u, std::thread::hardware_concurrency()));
  parallelBlocks(points.size(), threads, [&](std::size_t first, std::size_t last) {
    // Rows of a block are assembled here and copied column by column: writing one row
    // straight into the column-major result would touch one page per face.
    const auto rows = Eigen::Index(last - first);
    Eigen::MatrixXd blockPhi = Eigen::MatrixXd::Zero(rows, Eigen::Index(vertices.size()));
    Eigen::MatrixXd blockPsi(rows, Eigen::Index(faces.size()));
    PointSums sums(vertices.size());
    std::vector<double> distance(vertices.size());
    std::vector<double> logIntegral(edges.size());
    for (std::size_t i = first; i < last; ++i) {
      const Eigen::Index row = Eigen::Index(i - first);
      const Eigen::Vector3d& eta = points[i];
      for (std::size_t v = 0; v < vertices.size(); ++v)
        distance[v] = (vertices[v] - eta).norm();
      for (std::size_t e = 0; e < edges.size(); ++e) {
        const Edge& edge = edges[e];
        const Eigen::Vector3d toA = vertices[std::size_t(edge.a)] - eta;
        logIntegral[e] =
            edgeLogIntegral(edge.dir.dot(toA), edge.length, distance[std::size_t(edge.a)],
                            distance[std::size_t(edge.b)], edge.dir.cross(toA).squaredNorm());
      }
      for (std::size_t f = 0; f < faces.size(); ++f) {
        const auto& c = faces[f];
        const auto& fe = faceEdges[f];
        blockPsi(row, Eigen::Index(f)) = addFace(
            geometry[f], c, int(f), eta,
            {distance[std::size_t(c[0])], distance[std::size_t(c[1])], distance[std::size_t(c[2])]},
            {logIntegral[std::size_t(fe[0])], logIntegral[std::size_t(fe[1])],
             logIntegral[std::size_t(fe[2])]},
            tolerance, sums);
      }
      inside[i] = finishPoint(sums, faces, row, blockPhi, blockPsi);
    }
    result.phi.middleRows(Eigen::Index(first), rows) = blockPhi;
    result.psi.middleRows(Eigen::Index(first), rows) = blockPsi;
  });
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!inside[i]) result.outsidePoints.push_back(int(i));
  return result;
}

GreenCoordinatesResult computeGreenCoordinatesNaive(const TriMesh& cage,
                                                    const std::vector<Eigen::Vector3d>& points,
                                                    const GreenOptions& options) {
  checkCage(cage);
  const auto faces = cageFaces(cage);
  const double tolerance = options.epsilon * boundingDiagonal(cagePoints(cage));
  GreenCoordinatesResult result;
  const auto n = Eigen::Index(points.size());
  result.phi.setZero(n, Eigen::Index(cage.n_vertices()));
  result.psi.resize(n, Eigen::Index(faces.size()));
  PointSums sums(cage.n_vertices());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& eta = points[i];
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto& c = faces[f];
      const FaceGeometry g = faceGeometry(toEigen(cage.point(TriMesh::VertexHandle(c[0]))),
                                          toEigen(cage.point(TriMesh::VertexHandle(c[1]))),
                                          toEigen(cage.point(TriMesh::VertexHandle(c[2]))));
      std::array<double, 3> r{}, logIntegral{};
      for (std::size_t k = 0; k < 3; ++k)
        r[k] = (g.corner[k] - eta).norm();
      for (std::size_t k = 0; k < 3; ++k) {
        const Eigen::Vector3d toA = g.corner[k] - eta;
        logIntegral[k] = edgeLogIntegral(g.edgeDir[k].dot(toA), g.edgeLength[k], r[k],
                                         r[(k + 1) % 3], g.edgeDir[k].cross(toA).squaredNorm());
      }
      result.psi(Eigen::Index(i), Eigen::Index(f)) =
          addFace(g, c, int(f), eta, r, logIntegral, tolerance, sums);
    }
    if (!finishPoint(sums, faces, Eigen::Index(i), result.phi, result.psi))
      result.outsidePoints.push_back(int(i));
  }
  return result;
}

Eigen::VectorXd greenStretch(const TriMesh& sourceCage, const TriMesh& deformedCage) {
  const auto faces = cageFaces(sourceCage);
  const auto source = cagePoints(sourceCage);
  const auto deformed = cagePoints(deformedCage);
  Eigen::VectorXd stretch(Eigen::Index(faces.size()));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto [a, b, c] = faces[f];
    const Eigen::Vector3d u = source[std::size_t(b)] - source[std::size_t(a)];
    const Eigen::Vector3d v = source[std::size_t(c)] - source[std::size_t(a)];
    const Eigen::Vector3d u2 = deformed[std::size_t(b)] - deformed[std::size_t(a)];
    const Eigen::Vector3d v2 = deformed[std::size_t(c)] - deformed[std::size_t(a)];
    // LLCO08 section 3: |u'v^T - v'u^T|_F / (sqrt(8) area), which is lambda for a similarity.
    const double squared = u2.squaredNorm() * v.squaredNorm() - 2.0 * u2.dot(v2) * u.dot(v) +
                           v2.squaredNorm() * u.squaredNorm();
    stretch[Eigen::Index(f)] =
        std::sqrt(std::max(0.0, squared)) / (std::sqrt(8.0) * 0.5 * u.cross(v).norm());
  }
  return stretch;
}

std::vector<Eigen::Vector3d> applyGreenCoordinates(const Eigen::MatrixXd& phi,
                                                   const Eigen::MatrixXd& psi,
                                                   const TriMesh& sourceCage,
                                                   const TriMesh& deformedCage) {
  const auto faces = cageFaces(sourceCage);
  if (deformedCage.n_vertices() != sourceCage.n_vertices() || cageFaces(deformedCage) != faces) {
    std::ostringstream message;
    message << "the deformed cage (" << deformedCage.n_vertices() << " vertices, "
            << deformedCage.n_faces()
            << " faces) does not have the connectivity of the source cage ("
            << sourceCage.n_vertices() << " vertices, " << sourceCage.n_faces() << " faces)";
    throw CageError(message.str());
  }
  if (phi.cols() != Eigen::Index(sourceCage.n_vertices()) ||
      psi.cols() != Eigen::Index(faces.size()) || phi.rows() != psi.rows()) {
    std::ostringstream message;
    message << "the coordinates (phi " << phi.rows() << " x " << phi.cols() << ", psi "
            << psi.rows() << " x " << psi.cols() << ") were not computed for this cage ("
            << sourceCage.n_vertices() << " vertices, " << faces.size() << " faces)";
    throw CageError(message.str());
  }
  const auto deformed = cagePoints(deformedCage);
  Eigen::MatrixXd cageVertices(Eigen::Index(deformed.size()), 3);
  for (std::size_t v = 0; v < deformed.size(); ++v)
    cageVertices.row(Eigen::Index(v)) = deformed[v].transpose();
  const Eigen::VectorXd stretch = greenStretch(sourceCage, deformedCage);
  Eigen::MatrixXd scaledNormals(Eigen::Index(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto [a, b, c] = faces[f];
    const Eigen::Vector3d cross = (deformed[std::size_t(b)] - deformed[std::size_t(a)])
                                      .cross(deformed[std::size_t(c)] - deformed[std::size_t(a)]);
    const double norm = cross.norm();
    // A face collapsed to a segment has no normal; its stretch is then 0 as well.
    scaledNormals.row(Eigen::Index(f)) =
        norm > 0 ? Eigen::RowVector3d(stretch[Eigen::Index(f)] / norm * cross)
                 : Eigen::RowVector3d::Zero();
  }
  const Eigen::MatrixXd mapped = phi * cageVertices + psi * scaledNormals;
  std::vector<Eigen::Vector3d> result(std::size_t(mapped.rows()));
  for (std::size_t i = 0; i < result.size(); ++i)
    result[i] = mapped.row(Eigen::Index(i)).transpose();
  return result;
}

}  // namespace geobrush
