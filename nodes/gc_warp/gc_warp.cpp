#include "gc_warp.hpp"

#include "geobrush/parallel.hpp"
#include "geobrush/simd.hpp"
#include "green_kernel.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
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
// resets the sums; psiRow already holds the row's face terms. Returns whether the point lies
// inside (total solid angle 4 pi, not 0).
bool finishPoint(PointSums& sums, const std::vector<std::array<int, 3>>& faces, double* phiRow,
                 double* psiRow) {
  const double fourPi = 4.0 * std::numbers::pi;
  bool inside = std::abs(sums.solidAngle - fourPi) < 2.0 * std::numbers::pi;
  if (!sums.touching.empty()) {
    const double share = (fourPi - sums.solidAngle) / double(sums.touching.size());
    for (const auto& [face, hat, d] : sums.touching) {
      for (int l = 0; l < 3; ++l)
        sums.phi[std::size_t(faces[std::size_t(face)][std::size_t(l)])] +=
            hat[std::size_t(l)] * share;
      psiRow[face] -= d * share * kInvFourPi;
    }
    inside = true;
    sums.touching.clear();
  }
  for (std::size_t i = 0; i < sums.phi.size(); ++i) {
    phiRow[i] = sums.phi[i];
    sums.phi[i] = 0;
  }
  sums.solidAngle = 0;
  return inside;
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

namespace {

// The cage's per-face and per-edge data, computed once for all points, in the two forms the
// scalar path (FaceGeometry) and the vector kernel (flat arrays) read.
struct PreparedCage {
  struct Edge {
    int a, b;
    Eigen::Vector3d dir;
    double length;
  };
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;
  std::vector<std::array<int, 3>> faceEdges;  // edge k of a face runs from corner k to k + 1
  std::vector<Edge> edges;
  std::vector<FaceGeometry> geometry;
  double tolerance = 0;

  std::vector<double> flatVertex, flatEdgeDir, flatEdgeLength, flatFace;
  std::vector<int> flatEdgeEnd, flatFaceVertex, flatFaceEdge;

  PreparedCage(const TriMesh& cage, double epsilon);
  green_kernel::Cage kernelView() const;
};

PreparedCage::PreparedCage(const TriMesh& cage, double epsilon)
    : vertices(cagePoints(cage)), faces(cageFaces(cage)) {
  tolerance = epsilon * boundingDiagonal(vertices);
  // Every edge's integral of 1/r serves both its faces: computed once per point.
  std::map<std::pair<int, int>, int> edgeIndex;
  faceEdges.resize(faces.size());
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

  for (const auto& v : vertices)
    flatVertex.insert(flatVertex.end(), v.data(), v.data() + 3);
  for (const auto& e : edges) {
    flatEdgeEnd.insert(flatEdgeEnd.end(), {e.a, e.b});
    flatEdgeDir.insert(flatEdgeDir.end(), e.dir.data(), e.dir.data() + 3);
    flatEdgeLength.push_back(e.length);
  }
  for (std::size_t f = 0; f < faces.size(); ++f) {
    flatFaceVertex.insert(flatFaceVertex.end(), faces[f].begin(), faces[f].end());
    flatFaceEdge.insert(flatFaceEdge.end(), faceEdges[f].begin(), faceEdges[f].end());
    const FaceGeometry& g = geometry[f];
    const std::size_t at = flatFace.size();
    flatFace.resize(at + green_kernel::kFaceStride);
    double* out = flatFace.data() + at;
    for (int k = 0; k < 3; ++k) {
      out[green_kernel::kNormal + k] = g.normal[k];
      out[green_kernel::kHatWeight + k] = g.hatWeight[std::size_t(k)];
      for (int j = 0; j < 3; ++j) {
        out[green_kernel::kEdgeNormal + 3 * k + j] = g.edgeNormal[std::size_t(k)][j];
        out[green_kernel::kGram + 3 * k + j] = g.edgeNormalGram(k, j);
      }
    }
    out[green_kernel::kTwiceArea] = g.twiceArea;
  }
}

green_kernel::Cage PreparedCage::kernelView() const {
  green_kernel::Cage view;
  view.vertexCount = int(vertices.size());
  view.edgeCount = int(edges.size());
  view.faceCount = int(faces.size());
  view.vertex = flatVertex.data();
  view.edgeEnd = flatEdgeEnd.data();
  view.edgeDir = flatEdgeDir.data();
  view.edgeLength = flatEdgeLength.data();
  view.faceVertex = flatFaceVertex.data();
  view.faceEdge = flatFaceEdge.data();
  view.face = flatFace.data();
  view.tolerance = tolerance;
  return view;
}

// One point on the scalar path: its phi and psi rows. Returns whether it lies inside the cage.
class ScalarPoint {
 public:
  explicit ScalarPoint(const PreparedCage& cage)
      : cage_(cage),
        sums_(cage.vertices.size()),
        distance_(cage.vertices.size()),
        logIntegral_(cage.edges.size()) {}

  bool operator()(const Eigen::Vector3d& eta, double* phiRow, double* psiRow) {
    const auto& vertices = cage_.vertices;
    for (std::size_t v = 0; v < vertices.size(); ++v)
      distance_[v] = (vertices[v] - eta).norm();
    for (std::size_t e = 0; e < cage_.edges.size(); ++e) {
      const auto& edge = cage_.edges[e];
      const Eigen::Vector3d toA = vertices[std::size_t(edge.a)] - eta;
      logIntegral_[e] =
          edgeLogIntegral(edge.dir.dot(toA), edge.length, distance_[std::size_t(edge.a)],
                          distance_[std::size_t(edge.b)], edge.dir.cross(toA).squaredNorm());
    }
    for (std::size_t f = 0; f < cage_.faces.size(); ++f) {
      const auto& c = cage_.faces[f];
      const auto& fe = cage_.faceEdges[f];
      psiRow[f] = addFace(cage_.geometry[f], c, int(f), eta,
                          {distance_[std::size_t(c[0])], distance_[std::size_t(c[1])],
                           distance_[std::size_t(c[2])]},
                          {logIntegral_[std::size_t(fe[0])], logIntegral_[std::size_t(fe[1])],
                           logIntegral_[std::size_t(fe[2])]},
                          cage_.tolerance, sums_);
    }
    return finishPoint(sums_, cage_.faces, phiRow, psiRow);
  }

 private:
  const PreparedCage& cage_;
  PointSums sums_;
  std::vector<double> distance_;
  std::vector<double> logIntegral_;
};

// Points per parallel block: a multiple of 4, so that the grouping into vectors, and with it
// every bit of the result, is the same for any thread count.
constexpr std::size_t kBlock = 64;

}  // namespace

GreenCoordinatesResult computeGreenCoordinates(const TriMesh& cage,
                                               const std::vector<Eigen::Vector3d>& points,
                                               const GreenOptions& options) {
  checkCage(cage);
  const PreparedCage prepared(cage, options.epsilon);
  const green_kernel::Cage kernelCage = prepared.kernelView();
  const bool vectorized = simd::hasAvx2Fma();

  GreenCoordinatesResult result;
  const auto n = Eigen::Index(points.size());
  result.phi.resize(n, Eigen::Index(prepared.vertices.size()));
  result.psi.resize(n, Eigen::Index(prepared.faces.size()));
  std::vector<char> inside(points.size(), 1);
  parallelBlocks(
      points.size(), kBlock, options.threads,
      [&](std::size_t first, std::size_t last) {
        ScalarPoint scalar(prepared);
        std::vector<double> scratch(std::size_t(green_kernel::fourPointsScratchSize(kernelCage)) +
                                    4);
        double* aligned = scratch.data();
        while (reinterpret_cast<std::uintptr_t>(aligned) % 32 != 0)
          ++aligned;
        for (std::size_t i = first; i < last; i += 4) {
          const std::size_t count = std::min<std::size_t>(4, last - i);
          if (vectorized) {
            // A last group of fewer than four points repeats its last point in the spare lanes and
            // writes their rows to scratch rows.
            const double* lanes[4];
            double* phiRows[4];
            double* psiRows[4];
            std::vector<double> spare;
            if (count < 4)
              spare.resize(std::size_t(result.phi.cols() + result.psi.cols()) * (4 - count));
            for (std::size_t k = 0; k < 4; ++k) {
              const std::size_t p = i + std::min(k, count - 1);
              lanes[k] = points[p].data();
              if (k < count) {
                phiRows[k] = result.phi.row(Eigen::Index(p)).data();
                psiRows[k] = result.psi.row(Eigen::Index(p)).data();
              } else {
                phiRows[k] =
                    spare.data() + (k - count) * std::size_t(result.phi.cols() + result.psi.cols());
                psiRows[k] = phiRows[k] + result.phi.cols();
              }
            }
            bool in[4];
            if (green_kernel::fourPoints(kernelCage, lanes, phiRows, psiRows, in, aligned)) {
              for (std::size_t k = 0; k < count; ++k)
                inside[i + k] = in[k];
              continue;
            }
          }
          for (std::size_t p = i; p < i + count; ++p)
            inside[p] = scalar(points[p], result.phi.row(Eigen::Index(p)).data(),
                               result.psi.row(Eigen::Index(p)).data());
        }
      },
      options.progress);
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
    if (!finishPoint(sums, faces, result.phi.row(Eigen::Index(i)).data(),
                     result.psi.row(Eigen::Index(i)).data()))
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

namespace {

// applyGreenCoordinates for the rows `rows` (all rows when null).
std::vector<Eigen::Vector3d> applyToRows(const GreenCoordinates::Matrix& phi,
                                         const GreenCoordinates::Matrix& psi,
                                         const TriMesh& sourceCage, const TriMesh& deformedCage,
                                         const std::vector<int>* rows, int threads) {
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
  // One column per coefficient: v'_i for phi, s_j n(t'_j) for psi, padded to four doubles so
  // that each multiply-add is whole vector operations.
  const auto deformed = cagePoints(deformedCage);
  const Eigen::VectorXd stretch = greenStretch(sourceCage, deformedCage);
  const auto nv = Eigen::Index(deformed.size()), nf = Eigen::Index(faces.size());
  Eigen::Matrix<double, 4, Eigen::Dynamic> basis = Eigen::Matrix4Xd::Zero(4, nv + nf);
  for (Eigen::Index v = 0; v < nv; ++v)
    basis.col(v).head<3>() = deformed[std::size_t(v)];
  for (Eigen::Index f = 0; f < nf; ++f) {
    const auto [a, b, c] = faces[std::size_t(f)];
    const Eigen::Vector3d cross = (deformed[std::size_t(b)] - deformed[std::size_t(a)])
                                      .cross(deformed[std::size_t(c)] - deformed[std::size_t(a)]);
    const double norm = cross.norm();
    // A face collapsed to a segment has no normal; its stretch is then 0 as well.
    if (norm > 0) basis.col(nv + f).head<3>() = stretch[f] / norm * cross;
  }
  // Each row of phi and psi is read once, in order: the product is bound by memory bandwidth.
  if (rows) {
    for (int row : *rows)
      if (row < 0 || row >= phi.rows()) {
        throw CageError("row " + std::to_string(row) + " is not one of the " +
                        std::to_string(phi.rows()) + " points");
      }
  }
  std::vector<Eigen::Vector3d> result(rows ? rows->size() : std::size_t(phi.rows()));
  parallelBlocks(result.size(), kBlock, threads, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      const auto row = Eigen::Index(rows ? (*rows)[i] : int(i));
      const double* phiRow = phi.row(row).data();
      const double* psiRow = psi.row(row).data();
      Eigen::Vector4d sum = Eigen::Vector4d::Zero();
      for (Eigen::Index v = 0; v < nv; ++v)
        sum += phiRow[v] * basis.col(v);
      for (Eigen::Index f = 0; f < nf; ++f)
        sum += psiRow[f] * basis.col(nv + f);
      result[i] = sum.head<3>();
    }
  });
  return result;
}

}  // namespace

std::vector<Eigen::Vector3d> applyGreenCoordinates(const GreenCoordinates::Matrix& phi,
                                                   const GreenCoordinates::Matrix& psi,
                                                   const TriMesh& sourceCage,
                                                   const TriMesh& deformedCage, int threads) {
  return applyToRows(phi, psi, sourceCage, deformedCage, nullptr, threads);
}

std::vector<Eigen::Vector3d> applyGreenCoordinates(const GreenCoordinates::Matrix& phi,
                                                   const GreenCoordinates::Matrix& psi,
                                                   const TriMesh& sourceCage,
                                                   const TriMesh& deformedCage,
                                                   const std::vector<int>& rows, int threads) {
  return applyToRows(phi, psi, sourceCage, deformedCage, &rows, threads);
}

}  // namespace geobrush
