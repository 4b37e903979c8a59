#include "template_icp.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include "geobrush/cut_paste.hpp"

namespace geobrush {
namespace {

// Pairs closer than this fraction of the template's size are never outliers: once ICP has
// converged on exact data the median distance is rounding noise, and a multiple of it would
// drop pairs at random.
constexpr double kRejectFloor = 1e-12;

double diagonal(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0;
  Eigen::Vector3d low = points.front(), high = points.front();
  for (const auto& p : points) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  return (high - low).norm();
}

// Each border point with the template vertex nearest to it once the template is moved by
// `motion`: the border point is taken back by the inverse motion, so the tree stays on the
// unmoved template.
std::vector<IcpPair> closestPairs(const PointNeighbours& tree,
                                  std::span<const Eigen::Vector3d> border,
                                  const RigidMotion& motion) {
  std::vector<IcpPair> pairs;
  pairs.reserve(border.size());
  for (std::size_t i = 0; i < border.size(); ++i) {
    const Eigen::Vector3d back = motion.rotation.transpose() * (border[i] - motion.translation);
    pairs.push_back({int(i), tree.nearest(back, 1).front()});
  }
  return pairs;
}

std::vector<double> pairDistances(const PointNeighbours& tree,
                                  std::span<const Eigen::Vector3d> border,
                                  const RigidMotion& motion, const std::vector<IcpPair>& pairs) {
  std::vector<double> distance;
  distance.reserve(pairs.size());
  for (const IcpPair& pair : pairs)
    distance.push_back(
        (motion(tree.point(pair.templateVertex)) - border[std::size_t(pair.border)]).norm());
  return distance;
}

double median(std::vector<double> values) {
  const std::size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(half), values.end());
  const double upper = values[half];
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (*std::max_element(values.begin(), values.begin() + std::ptrdiff_t(half)) + upper);
}

double rms(const std::vector<double>& distance) {
  double sum = 0;
  for (double d : distance)
    sum += d * d;
  return distance.empty() ? 0.0 : std::sqrt(sum / double(distance.size()));
}

struct Pairing {
  std::vector<IcpPair> pairs;
  std::vector<double> distance;
  int rejected = 0;
};

// The closest pairs under `motion`, those farther than reject x their median (and than the floor)
// left out. With reject >= 1 the pairs up to the median stay, so at least one does.
Pairing pairAndReject(const PointNeighbours& tree, std::span<const Eigen::Vector3d> border,
                      const RigidMotion& motion, double reject, double floor) {
  const auto pairs = closestPairs(tree, border, motion);
  const auto distance = pairDistances(tree, border, motion, pairs);
  const double limit = reject == 0 ? std::numeric_limits<double>::infinity()
                                   : reject * std::max(median(distance), floor);
  Pairing kept;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (distance[i] > limit) {
      ++kept.rejected;
      continue;
    }
    kept.pairs.push_back(pairs[i]);
    kept.distance.push_back(distance[i]);
  }
  return kept;
}

RigidMotion fitPairs(const PointNeighbours& tree, std::span<const Eigen::Vector3d> border,
                     const std::vector<IcpPair>& pairs) {
  std::vector<Eigen::Vector3d> from, to;
  for (const IcpPair& pair : pairs) {
    from.push_back(tree.point(pair.templateVertex));
    to.push_back(border[std::size_t(pair.border)]);
  }
  return fitRigidMotion(from, to);
}

void checkInputs(const PointNeighbours& tree, std::span<const Eigen::Vector3d> border,
                 const TemplateIcpOptions& options) {
  if (tree.size() == 0) throw TemplateIcpError("template", "the template has no vertices");
  if (border.empty()) throw TemplateIcpError("border", "the border has no points");
  for (std::size_t i = 0; i < border.size(); ++i)
    if (!border[i].allFinite())
      throw TemplateIcpError("border", "border point " + std::to_string(i) + " is not finite");
  if (options.iterations < 0)
    throw TemplateIcpError("iterations", "the iteration count must not be negative");
  if (!(options.reject == 0 || options.reject >= 1))
    throw TemplateIcpError("reject",
                           "reject must be 0 (keep every pair) or at least 1 (a multiple of the "
                           "median pair distance)");
}

// The explicit pairs in border order; throws for one out of range or a border point given twice.
std::vector<IcpPair> checkedExplicitPairs(const PointNeighbours& tree,
                                          std::span<const Eigen::Vector3d> border,
                                          std::vector<IcpPair> pairs) {
  for (const IcpPair& pair : pairs) {
    if (pair.border < 0 || std::size_t(pair.border) >= border.size())
      throw TemplateIcpError("explicit_pairs", "border index " + std::to_string(pair.border) +
                                                   " is out of range: the border has " +
                                                   std::to_string(border.size()) + " points");
    if (pair.templateVertex < 0 || std::size_t(pair.templateVertex) >= tree.size())
      throw TemplateIcpError("explicit_pairs", "template vertex " +
                                                   std::to_string(pair.templateVertex) +
                                                   " is out of range: the template has " +
                                                   std::to_string(tree.size()) + " vertices");
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const IcpPair& a, const IcpPair& b) { return a.border < b.border; });
  for (std::size_t i = 1; i < pairs.size(); ++i)
    if (pairs[i].border == pairs[i - 1].border)
      throw TemplateIcpError(
          "explicit_pairs", "border index " + std::to_string(pairs[i].border) + " is paired twice");
  return pairs;
}

TemplateIcpResult solveExplicit(const PointNeighbours& tree,
                                std::span<const Eigen::Vector3d> border,
                                const std::vector<IcpPair>& explicitPairs) {
  TemplateIcpResult result;
  result.pairs = checkedExplicitPairs(tree, border, explicitPairs);
  result.rmsBefore = rms(pairDistances(tree, border, result.motion, result.pairs));
  result.motion = fitPairs(tree, border, result.pairs);
  result.iterations = 1;
  result.rmsAfter = rms(pairDistances(tree, border, result.motion, result.pairs));
  result.rmsAllPairs = result.rmsAfter;
  return result;
}

}  // namespace

RigidMotion fitRigidMotion(std::span<const Eigen::Vector3d> from,
                           std::span<const Eigen::Vector3d> to) {
  if (from.empty() || from.size() != to.size())
    throw std::invalid_argument("a rigid fit needs equally many points on both sides, at least 1");
  Eigen::Vector3d fromCentre = Eigen::Vector3d::Zero(), toCentre = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i) {
    fromCentre += from[i];
    toCentre += to[i];
  }
  fromCentre /= double(from.size());
  toCentre /= double(to.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i)
    covariance += (from[i] - fromCentre) * (to[i] - toCentre).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  // A reflection fits better than any rotation: flip the direction of the smallest singular
  // value, which costs least (Kabsch).
  Eigen::Vector3d sign(1, 1, 1);
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) sign.z() = -1;
  RigidMotion motion;
  motion.rotation = svd.matrixV() * sign.asDiagonal() * svd.matrixU().transpose();
  motion.translation = toCentre - motion.rotation * fromCentre;
  return motion;
}

TriMesh moveRigidly(const TriMesh& mesh, const RigidMotion& motion) {
  TriMesh moved = mesh;
  for (const auto v : moved.vertices())
    moved.set_point(v, toPoint(motion(pointOf(moved, v))));
  return moved;
}

std::vector<IcpPair> icpPairsFromRows(const std::vector<double>& rows) {
  if (rows.size() % kIcpPairRowSize != 0)
    throw TemplateIcpError("explicit_pairs",
                           "explicit pairs come in rows of 2 (border index, template vertex)");
  std::vector<IcpPair> pairs;
  for (std::size_t i = 0; i < rows.size(); i += kIcpPairRowSize) {
    for (std::size_t j = i; j < i + kIcpPairRowSize; ++j)
      if (!(rows[j] >= 0 && rows[j] <= std::numeric_limits<int>::max() &&
            rows[j] == std::floor(rows[j])))
        throw TemplateIcpError("explicit_pairs",
                               "row " + std::to_string(i / kIcpPairRowSize) +
                                   " holds an entry that is not a non-negative integer index");
    pairs.push_back({int(rows[i]), int(rows[i + 1])});
  }
  return pairs;
}

namespace {

Eigen::Vector3d vertexCentroid(const TriMesh& mesh, const std::vector<int>& vertices) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int v : vertices)
    sum += pointOf(mesh, v);
  return sum / double(vertices.size());
}

std::vector<int> allVertices(const TriMesh& mesh) {
  std::vector<int> all(mesh.n_vertices());
  std::iota(all.begin(), all.end(), 0);
  return all;
}

// Twice the sum of the faces' vector areas, and their total area.
std::pair<Eigen::Vector3d, double> vectorArea(const TriMesh& mesh) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double area = 0;
  for (const auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    const Eigen::Vector3d a = pointOf(mesh, mesh.from_vertex_handle(h));
    const Eigen::Vector3d b = pointOf(mesh, mesh.to_vertex_handle(h));
    const Eigen::Vector3d c = pointOf(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    sum += n;
    area += n.norm();
  }
  return {sum, area};
}

}  // namespace

RigidMotion frameAlignment(const TriMesh& templateMesh, const TriMesh& holed,
                           const std::vector<int>& border) {
  RigidMotion motion;
  const auto [templateNormal, templateArea] = vectorArea(templateMesh);
  Eigen::Vector3d surfaceNormal = Eigen::Vector3d::Zero();
  const std::vector<Eigen::Vector3d> normals = vertexNormals(holed);
  for (int v : border)
    surfaceNormal += normals[std::size_t(v)];
  // A mean normal under a tenth of the area: the template faces every way (closed or a tube).
  if (templateNormal.norm() > 0.1 * templateArea && surfaceNormal.norm() > 0)
    motion.rotation =
        Eigen::Quaterniond::FromTwoVectors(templateNormal, surfaceNormal).toRotationMatrix();
  motion.translation = vertexCentroid(holed, border) -
                       motion.rotation * vertexCentroid(templateMesh, allVertices(templateMesh));
  return motion;
}

namespace {

// ICP from one start: pair, reject, fit, until the pairs stop changing or the rounds run out.
TemplateIcpResult alignFrom(const PointNeighbours& templatePoints,
                            std::span<const Eigen::Vector3d> border,
                            const TemplateIcpOptions& options, const RigidMotion& start) {
  const double floor = kRejectFloor * diagonal(templatePoints.points());
  TemplateIcpResult result;
  result.motion = start;
  Pairing pairing = pairAndReject(templatePoints, border, result.motion, options.reject, floor);
  result.rmsBefore = rms(pairing.distance);
  while (result.iterations < options.iterations) {
    result.motion = fitPairs(templatePoints, border, pairing.pairs);
    ++result.iterations;
    Pairing next = pairAndReject(templatePoints, border, result.motion, options.reject, floor);
    // The same pairs would give the same motion again: converged.
    const bool converged = next.pairs == pairing.pairs;
    pairing = std::move(next);
    if (converged) break;
  }
  result.rejected = pairing.rejected;
  result.rmsAfter = rms(pairing.distance);
  // Rejection only guards the fit: the warp must meet every border point.
  Pairing all = pairAndReject(templatePoints, border, result.motion, 0, floor);
  result.pairs = std::move(all.pairs);
  result.rmsAllPairs = rms(all.distance);
  return result;
}

}  // namespace

TemplateIcpResult alignTemplate(const PointNeighbours& templatePoints,
                                std::span<const Eigen::Vector3d> border,
                                const TemplateIcpOptions& options) {
  checkInputs(templatePoints, border, options);
  if (!options.explicitPairs.empty())
    return solveExplicit(templatePoints, border, options.explicitPairs);
  TemplateIcpResult best = alignFrom(templatePoints, border, options, options.initial);
  for (std::size_t i = 0; i < options.otherStarts.size(); ++i) {
    TemplateIcpResult other = alignFrom(templatePoints, border, options, options.otherStarts[i]);
    other.start = int(i) + 1;
    if (other.rmsAllPairs < best.rmsAllPairs) best = std::move(other);
  }
  return best;
}

}  // namespace geobrush
