#include "geodesic_region.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "geobrush/cut_paste.hpp"
#include "geobrush/intersection.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

std::string number(double x) {
  std::ostringstream out;
  out.precision(4);
  out << x;
  return out.str();
}

double cross2(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The polygon's corner angle: the turn from side a to side b, counter-clockwise positive.
double turn(const Vector2d& a, const Vector2d& b) {
  return std::atan2(cross2(a, b), a.dot(b));
}

GeodesicRegionError walkError(WalkStop stop, int side, const GeodesicWalkResult& walk, int budget) {
  const std::string where =
      side < 0 ? "toward the first corner" : "on side " + std::to_string(side);
  switch (stop) {
    case WalkStop::Boundary:
      return {"placement", "the walk " + where + " reaches the target's boundary near face " +
                               std::to_string(walk.face) +
                               ": move the origin away from it or use a smaller scale"};
    case WalkStop::Degenerate:
      return {"target", "the walk " + where + " meets a degenerate face near face " +
                            std::to_string(walk.face) + ": repair the target mesh"};
    default:
      return {"target", "the walk " + where + " crosses more than " + std::to_string(budget) +
                            " faces without ending (a degenerate target?)"};
  }
}

// The walk's straight pieces of positive length.
void appendPieces(const GeodesicWalkResult& walk, std::vector<LoopPiece>& pieces) {
  for (std::size_t i = 0; i < walk.faces.size(); ++i)
    if (walk.points[i] != walk.points[i + 1])
      pieces.push_back({walk.faces[i], walk.points[i], walk.points[i + 1]});
}

// One straight side, its pieces appended to `pieces`; throws unless it walked its whole length.
GeodesicWalkResult walkSide(const TriMesh& target, int face, const Vector3d& point,
                            const Vector3d& direction, double length, int side,
                            const GeodesicRegionOptions& options, std::vector<LoopPiece>* pieces) {
  const GeodesicWalkResult walk =
      walkStraightest(target, face, point, direction, length, options.walk);
  if (walk.stop != WalkStop::Completed)
    throw walkError(walk.stop, side, walk, walkFaceBudget(target, length, options.walk));
  if (pieces) appendPieces(walk, *pieces);
  return walk;
}

// Re-walks the last side from `from` with its heading and length corrected until it ends at
// `goal` (Newton steps on the flat approximation: turning the heading by t moves the end
// sideways by about length t); the walk that ends nearest to it.
GeodesicWalkResult aimLastSide(const TriMesh& target, const SurfacePoint& from,
                               const Vector3d& direction, const GeodesicWalkResult& first,
                               const Vector3d& goal, int side, double tolerance,
                               const GeodesicRegionOptions& options) {
  GeodesicWalkResult best = first, walk = first;
  double heading = 0, length = first.length;
  for (int i = 0; i < options.aimIterations && (best.point - goal).norm() > tolerance; ++i) {
    const Vector3d miss = goal - walk.point;
    const Vector3d normal = faceUnitNormal(target, walk.face);
    length = std::max(length + walk.direction.dot(miss), 0.0);
    if (length > 0) heading += normal.dot(walk.direction.cross(miss)) / length;
    const Vector3d aimed = rotateInFace(target, from.face, direction, heading);
    walk = walkSide(target, from.face, from.point, aimed, length, side, options, nullptr);
    if ((walk.point - goal).norm() < (best.point - goal).norm()) best = walk;
  }
  return best;
}

bool shareVertex(const TriMesh& mesh, int f, int g) {
  for (auto a : mesh.fv_range(TriMesh::FaceHandle(f)))
    for (auto b : mesh.fv_range(TriMesh::FaceHandle(g)))
      if (a == b) return true;
  return false;
}

// The last side: walked as the polygon says (its miss of corner 0 is the closing gap), then
// re-aimed at corner 0 so that the loop closes. Where a vertex of the target hides corner 0 from
// every heading, the loop closes through the faces around that vertex.
void closeLoop(const TriMesh& target, const SurfacePoint& from, const Vector3d& heading,
               double length, const GeodesicRegionOptions& options, WalkedLoop& loop) {
  const int side = int(loop.corner.size()) - 1;
  const Vector3d goal = loop.corner.front();
  const int goalFace = loop.cornerFace.front();
  GeodesicWalkResult walk =
      walkSide(target, from.face, from.point, heading, length, side, options, nullptr);
  const double shapedGap = (walk.point - goal).norm();
  walk = aimLastSide(target, from, heading, walk, goal, side, 1e-12 * loop.length, options);
  if (walk.face != goalFace && !shareVertex(target, walk.face, goalFace))
    throw GeodesicRegionError(
        "placement", "the walked loop misses closing by " + number(loop.gap) + " (" +
                         number(100 * loop.gap / loop.length) + "% of its length; " +
                         number(shapedGap) +
                         " once bent and stretched to close) and its last side cannot be aimed "
                         "at its first corner: use a smaller scale, or move the origin where the "
                         "target curves less");
  loop.vertices += walk.vertices;
  appendPieces(walk, loop.pieces);
  // Inside one face the last piece may as well end at corner 0 itself.
  if (walk.face == goalFace && !loop.pieces.empty() && loop.pieces.back().face == goalFace)
    loop.pieces.back().to = goal;
}

// The loop's pieces in each face, by face (in increasing face order, for deterministic output).
std::map<int, std::vector<int>> piecesByFace(const WalkedLoop& loop) {
  std::map<int, std::vector<int>> byFace;
  for (int i = 0; i < int(loop.pieces.size()); ++i)
    byFace[loop.pieces[std::size_t(i)].face].push_back(i);
  return byFace;
}

// Whether pieces i and j follow one another round the loop (sharing an end).
bool consecutive(int i, int j, int count) {
  return std::abs(i - j) == 1 || std::abs(i - j) == count - 1;
}

double pointSegmentDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Whether two pieces in the plane with this normal cross or come within `tolerance`.
bool piecesMeet(const LoopPiece& s, const LoopPiece& t, const Vector3d& normal, double tolerance) {
  auto side = [&](const Vector3d& a, const Vector3d& b, const Vector3d& x) {
    return normal.dot((b - a).cross(x - a));
  };
  const double o1 = side(s.from, s.to, t.from), o2 = side(s.from, s.to, t.to);
  const double o3 = side(t.from, t.to, s.from), o4 = side(t.from, t.to, s.to);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return std::min({pointSegmentDistance(t.from, s.from, s.to),
                   pointSegmentDistance(t.to, s.from, s.to),
                   pointSegmentDistance(s.from, t.from, t.to),
                   pointSegmentDistance(s.to, t.from, t.to)}) <= tolerance;
}

void requireSimpleLoop(const TriMesh& target, const WalkedLoop& loop,
                       const std::map<int, std::vector<int>>& byFace) {
  const int count = int(loop.pieces.size());
  const double tolerance = 1e-12 * loop.length;
  for (const auto& [face, pieces] : byFace) {
    const Vector3d normal = faceUnitNormal(target, face);
    for (std::size_t a = 0; a < pieces.size(); ++a)
      for (std::size_t b = a + 1; b < pieces.size(); ++b) {
        if (consecutive(pieces[a], pieces[b], count)) continue;
        if (piecesMeet(loop.pieces[std::size_t(pieces[a])], loop.pieces[std::size_t(pieces[b])],
                       normal, tolerance))
          throw GeodesicRegionError(
              "placement", "the walked loop crosses or touches itself in target face " +
                               std::to_string(face) +
                               ": use a smaller scale, or move the origin where the target "
                               "curves less");
      }
  }
}

// +1 where `x` (in `face`'s plane) lies left of the loop's pieces in that face, -1 right, 0 on
// them: decided by the nearest piece, at a corner shared by two pieces by the wedge they make.
int sideOfLoop(const WalkedLoop& loop, const std::vector<int>& pieces, const Vector3d& normal,
               const Vector3d& x) {
  const int count = int(loop.pieces.size());
  int nearest = pieces.front();
  double best = std::numeric_limits<double>::infinity();
  for (int i : pieces) {
    const double d =
        pointSegmentDistance(x, loop.pieces[std::size_t(i)].from, loop.pieces[std::size_t(i)].to);
    if (d < best) best = d, nearest = i;
  }
  const LoopPiece& s = loop.pieces[std::size_t(nearest)];
  const Vector3d along = s.to - s.from;
  const double t = (x - s.from).dot(along) / along.squaredNorm();
  auto leftOf = [&](const LoopPiece& p, const Vector3d& y) {
    return normal.dot((p.to - p.from).normalized().cross(y - p.from));
  };
  const int neighbour = t >= 1   ? (nearest + 1) % count
                        : t <= 0 ? (nearest + count - 1) % count
                                 : -1;
  const bool wedge = neighbour >= 0 &&
                     std::find(pieces.begin(), pieces.end(), neighbour) != pieces.end() &&
                     loop.pieces[std::size_t(neighbour)].face == s.face;
  const double tiny = 1e-12 * along.norm();
  if (!wedge) {
    const double l = leftOf(s, x);
    return l > tiny ? 1 : l < -tiny ? -1 : 0;
  }
  const LoopPiece& in = loop.pieces[std::size_t(t >= 1 ? nearest : neighbour)];
  const LoopPiece& out = loop.pieces[std::size_t(t >= 1 ? neighbour : nearest)];
  const double l1 = leftOf(in, x), l2 = leftOf(out, x);
  const bool turnsLeft = normal.dot((in.to - in.from).cross(out.to - out.from)) > 0;
  const bool left = turnsLeft ? (l1 > 0 && l2 > 0) : (l1 > 0 || l2 > 0);
  return left ? 1 : -1;
}

// Per face: 1 where an edge with a crossed face lies on the loop's left, 2 on its right, 3 both.
std::vector<std::uint8_t> sideMarks(const TriMesh& target, const WalkedLoop& loop,
                                    const std::map<int, std::vector<int>>& byFace,
                                    const std::vector<char>& crossed) {
  std::vector<std::uint8_t> marks(target.n_faces(), 0);
  for (const auto& [face, pieces] : byFace) {
    const Vector3d normal = faceUnitNormal(target, face);
    for (auto h : target.fh_range(TriMesh::FaceHandle(face))) {
      const auto g = target.face_handle(target.opposite_halfedge_handle(h));
      if (!g.is_valid() || crossed[std::size_t(g.idx())]) continue;
      const auto a = target.point(target.from_vertex_handle(h));
      const auto b = target.point(target.to_vertex_handle(h));
      const Vector3d middle(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]));
      const int side = sideOfLoop(loop, pieces, normal, middle);
      if (side != 0) marks[std::size_t(g.idx())] |= side > 0 ? 1 : 2;
    }
  }
  return marks;
}

GeodesicRegionError touchesItself(int face) {
  return GeodesicRegionError("placement",
                             "the walked loop touches itself: the faces around target face " +
                                 std::to_string(face) +
                                 " lie on both of its sides: use a smaller scale, or move the "
                                 "origin where the target curves less");
}

// The faces not crossed that the loop encloses: a flood through uncrossed faces from those
// marked on its inner side, which must not reach one marked on the outer side. Costs the
// region's size, not the target's.
std::vector<int> enclosedFaces(const TriMesh& target, const std::vector<char>& crossed,
                               const std::vector<std::uint8_t>& marks, bool innerLeft) {
  const std::uint8_t inner = innerLeft ? 1 : 2, outer = innerLeft ? 2 : 1;
  std::vector<char> reached(target.n_faces(), 0);
  std::vector<int> queue;
  for (std::size_t f = 0; f < marks.size(); ++f)
    if (marks[f] & inner) {
      if (marks[f] & outer) throw touchesItself(int(f));
      reached[f] = 1;
      queue.push_back(int(f));
    }
  for (std::size_t next = 0; next < queue.size(); ++next)
    for (auto g : target.ff_range(TriMesh::FaceHandle(queue[next]))) {
      const std::size_t k = std::size_t(g.idx());
      if (crossed[k] || reached[k]) continue;
      if (marks[k] & outer) throw touchesItself(g.idx());
      reached[k] = 1;
      queue.push_back(g.idx());
    }
  std::sort(queue.begin(), queue.end());
  return queue;
}

void requirePlacement(const MeshPtr& target, const Parameterization& placement) {
  if (!placement.canvas || !placement.canvas->source)
    throw GeodesicRegionError("placement", "the placement has no canvas on a mesh");
  if (placement.canvas->source != target &&
      placement.canvas->source->contentHash() != target->contentHash())
    throw GeodesicRegionError("placement",
                              "the placement was made on another mesh than the target: connect "
                              "the same mesh to both");
  const Frame& f = placement.origin;
  if (!f.point.allFinite() || !f.normal.allFinite() || !f.uAxis.allFinite() ||
      !f.vAxis.allFinite() || !(f.normal.norm() > 0.5))
    throw GeodesicRegionError("placement", "the placement's origin frame is not finite");
  if (!std::isfinite(placement.scale) || !(placement.scale > 0))
    throw GeodesicRegionError(
        "placement",
        "the placement's scale must be a finite number > 0, not " + number(placement.scale));
}

// The placement's origin on the target: on the target face under its canvas' origin face where
// the canvas says which that is (no search over the whole target on every move), else the
// nearest point of the target.
SurfacePoint startPoint(const TriMesh& mesh, const Parameterization& placement) {
  const Canvas& canvas = *placement.canvas;
  if (canvas.originFace < 0 || std::size_t(canvas.originFace) >= canvas.sourceFace.size())
    return nearestSurfacePoint(mesh, placement.origin.point);
  SurfacePoint start;
  start.face = canvas.sourceFace[std::size_t(canvas.originFace)];
  const Triangle3 t = faceTriangle(mesh, start.face);
  start.point = closestPointOnTriangle(placement.origin.point, t[0], t[1], t[2]);
  start.distance = (start.point - placement.origin.point).norm();
  return start;
}

}  // namespace

double signedArea2(const std::vector<Vector2d>& polygon) {
  double sum = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    sum += cross2(polygon[i], polygon[(i + 1) % polygon.size()]);
  return sum;
}

std::vector<Vector2d> basePolygon(const Parameterization& base) {
  if (!base.canvas) throw GeodesicRegionError("base", "the base parameterization has no canvas");
  const Canvas& canvas = *base.canvas;
  if (base.uv.size() != canvas.surface.n_vertices())
    throw GeodesicRegionError("base", "the base has " + std::to_string(base.uv.size()) +
                                          " uv for " + std::to_string(canvas.surface.n_vertices()) +
                                          " vertices");
  std::vector<Vector2d> polygon;
  for (int v : canvas.boundary) {
    if (v < 0 || v >= int(base.uv.size()) || !base.uv[std::size_t(v)].allFinite())
      throw GeodesicRegionError(
          "base", "the base's boundary vertex " + std::to_string(v) + " has no finite uv");
    polygon.push_back(base.uv[std::size_t(v)]);
  }
  const int m = int(polygon.size());
  if (m < 3)
    throw GeodesicRegionError("base", "the base's boundary has " + std::to_string(m) +
                                          " corners; a polygon needs at least 3");
  for (int i = 0; i < m; ++i)
    if (polygon[std::size_t(i)] == polygon[std::size_t((i + 1) % m)])
      throw GeodesicRegionError("base", "corners " + std::to_string(i) + " and " +
                                            std::to_string((i + 1) % m) +
                                            " of the base's boundary coincide in uv");
  const auto [i, j] = firstSelfCrossing(polygon);
  if (i >= 0)
    throw GeodesicRegionError("base", "the base's boundary crosses itself in uv (sides " +
                                          std::to_string(i) + " and " + std::to_string(j) +
                                          "): use a base whose parameterization is one-to-one");
  if (signedArea2(polygon) == 0)
    throw GeodesicRegionError("base", "the base's boundary encloses no area in uv");
  return polygon;
}

std::pair<Vector3d, Vector3d> startAxes(const TriMesh& target, int face, const Frame& frame) {
  const Vector3d n = faceUnitNormal(target, face);
  if (n.isZero())
    throw GeodesicRegionError("target", "the face under the origin (" + std::to_string(face) +
                                            ") is degenerate: repair the target mesh");
  if (!(frame.normal.normalized().dot(n) > 0))
    throw GeodesicRegionError("placement",
                              "the origin frame's normal faces away from the target face under "
                              "it: use the target DEM's output for this target");
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(frame.normal, n);
  return {rotateInFace(target, face, q * frame.uAxis, 0),
          rotateInFace(target, face, q * frame.vAxis, 0)};
}

// How the sides are walked: side i's length times 1 + stretch . (cos t_i, sin t_i) for its
// direction t_i in the domain (a stretch the closure of a polygon feels, unlike a linear map of
// its sides), and each corner's turn plus `bend` times the length of the side it starts (a
// uniform geodesic curvature added to the loop).
struct LoopShape {
  Vector2d stretch = Vector2d::Zero();
  double bend = 0;
};

// Paper, "geodesic walk": t_{i+1} = the arrival direction turned by atan2(a x b, a . b). Walks to
// corner 0 and round the corners, the last side included; `loop` gets the corners and, when
// `keepPieces`, the pieces of every side but the last. Returns the last side's start, heading and
// length, and sets `end` to where that side, walked as told, ends.
struct LastSide {
  SurfacePoint from;
  Vector3d heading;
  double length = 0;
  Vector3d end;
};
LastSide walkCorners(const TriMesh& target, const SurfacePoint& start,
                     const std::pair<Vector3d, Vector3d>& axes, double scale,
                     const std::vector<Vector2d>& polygon, const LoopShape& shape,
                     const GeodesicRegionOptions& options, bool keepPieces, WalkedLoop& loop) {
  const int m = int(polygon.size());
  const auto& [u, v] = axes;
  auto side = [&](int i) -> Vector2d {
    return polygon[std::size_t((i + 1) % m)] - polygon[std::size_t(i)];
  };
  auto sideLength = [&](int i) {
    return (1 + shape.stretch.dot(side(i).normalized())) * scale * side(i).norm();
  };
  SurfacePoint at = start;
  Vector3d heading;
  const Vector2d p0 = polygon.front();
  if (p0.norm() > 1e-12 * loop.length / scale) {
    const GeodesicWalkResult first =
        walkSide(target, start.face, start.point, (p0.x() * u + p0.y() * v).normalized(),
                 scale * p0.norm(), -1, options, nullptr);
    at = {first.face, first.point, 0};
    heading = rotateInFace(target, at.face, first.direction,
                           turn(p0, side(0)) + shape.bend * sideLength(0));
  } else {
    heading = rotateInFace(target, at.face, side(0).x() * u + side(0).y() * v,
                           shape.bend * sideLength(0));
  }
  loop.cornerFace.clear();
  loop.corner.clear();
  loop.vertices = 0;
  for (int i = 0; i < m; ++i) {
    loop.cornerFace.push_back(at.face);
    loop.corner.push_back(at.point);
    if (i == m - 1) break;
    const GeodesicWalkResult walk = walkSide(target, at.face, at.point, heading, sideLength(i), i,
                                             options, keepPieces ? &loop.pieces : nullptr);
    loop.vertices += walk.vertices;
    at = {walk.face, walk.point, 0};
    heading = rotateInFace(target, at.face, walk.direction,
                           turn(side(i), side(i + 1)) + shape.bend * sideLength(i + 1));
  }
  const GeodesicWalkResult last =
      walkSide(target, at.face, at.point, heading, sideLength(m - 1), m - 1, options, nullptr);
  return {at, heading, sideLength(m - 1), last.point};
}

constexpr double kStretchWeight = 10;
constexpr double kMaxStep = 0.25;
constexpr double kClosingShare = 0.05;

// The loop's shape that closes it: on a curved target the polygon's own turns do not add up to
// a closed loop (Gauss-Bonnet: the heading comes back turned by the curvature enclosed), so the
// bend and stretch of least weighted norm that bring the last
// side's end onto corner 0 are found by Newton steps on finite differences; the shape whose end
// lands nearest.
LoopShape closingShape(const TriMesh& target, const SurfacePoint& start,
                       const std::pair<Vector3d, Vector3d>& axes, double scale,
                       const std::vector<Vector2d>& polygon, const GeodesicRegionOptions& options,
                       WalkedLoop& loop) {
  Vector3d e1 = Vector3d::Zero(), e2 = Vector3d::Zero();
  auto miss = [&](const LoopShape& shape) {
    WalkedLoop trial = loop;
    const LastSide last =
        walkCorners(target, start, axes, scale, polygon, shape, options, false, trial);
    if (e1.isZero()) {
      const Vector3d normal = faceUnitNormal(target, trial.cornerFace.front());
      e1 = normal.unitOrthogonal();
      e2 = normal.cross(e1);
    }
    const Vector3d d = last.end - trial.corner.front();
    return Vector2d(d.dot(e1), d.dot(e2));
  };
  // The unknowns: the total extra turn, and the stretch weighed ten times as much, so that the
  // turn the enclosed curvature calls for comes first and the sides keep their lengths.
  auto shaped = [&](const LoopShape& shape, const Eigen::Vector3d& x) {
    return LoopShape{shape.stretch + x.tail<2>() / kStretchWeight,
                     shape.bend + x.x() / loop.length};
  };
  LoopShape best, shape;
  Vector2d current = miss(best), bestMiss = current;
  loop.gap = current.norm();
  // Close enough for the last side's aim to finish the loop: a small share of a side.
  const double tolerance = kClosingShare * loop.length / double(polygon.size()), delta = 1e-4;
  for (int i = 0; i < options.closingIterations && bestMiss.norm() > tolerance; ++i) {
    // A shape whose walk leaves the target or the stretch's range ends the search.
    try {
      Eigen::Matrix<double, 2, 3> jacobian;
      for (int k = 0; k < 3; ++k)
        jacobian.col(k) = (miss(shaped(shape, delta * Eigen::Vector3d::Unit(k))) - current) / delta;
      const Eigen::Matrix2d normal = jacobian * jacobian.transpose();
      if (!(std::abs(normal.determinant()) > 0)) break;
      Eigen::Vector3d step = -jacobian.transpose() * normal.inverse() * current;
      if (!step.allFinite()) break;
      // Damped: a step of at most kMaxStep in the weighted unknowns (radians of total turn),
      // halved while it does not bring the end closer.
      step *= std::min(1.0, kMaxStep / step.norm());
      LoopShape next = shaped(shape, step);
      Vector2d nextMiss = miss(next);
      for (int halvings = 0; halvings < 4 && nextMiss.norm() >= current.norm(); ++halvings) {
        step /= 2;
        next = shaped(shape, step);
        nextMiss = miss(next);
      }
      if (!(next.stretch.norm() < 0.5)) break;
      shape = next;
      current = nextMiss;
    } catch (const std::invalid_argument&) {
      break;
    }
    if (current.norm() < bestMiss.norm()) {
      best = shape;
      bestMiss = current;
    }
  }
  return best;
}

WalkedLoop walkLoop(const TriMesh& target, const SurfacePoint& start, const Frame& frame,
                    double scale, const std::vector<Vector2d>& polygon,
                    const GeodesicRegionOptions& options) {
  const int m = int(polygon.size());
  WalkedLoop loop;
  loop.start = start;
  for (int i = 0; i < m; ++i)
    loop.length += scale * (polygon[std::size_t((i + 1) % m)] - polygon[std::size_t(i)]).norm();
  const auto axes = startAxes(target, start.face, frame);
  const LoopShape shape = closingShape(target, start, axes, scale, polygon, options, loop);
  loop.stretch = shape.stretch;
  loop.bend = shape.bend;
  const LastSide last =
      walkCorners(target, start, axes, scale, polygon, shape, options, true, loop);
  closeLoop(target, last.from, last.heading, last.length, options, loop);
  return loop;
}

// Paper, "geodesic walk": region = the faces crossed plus a flood fill on the inner side.
std::pair<std::vector<int>, std::vector<int>> loopFaces(const TriMesh& target,
                                                        const WalkedLoop& loop, bool innerLeft) {
  const auto byFace = piecesByFace(loop);
  if (byFace.empty()) throw GeodesicRegionError("placement", "the walked loop crosses no face");
  requireSimpleLoop(target, loop, byFace);
  std::vector<char> crossed(target.n_faces(), 0);
  std::vector<int> crossedFaces;
  for (const auto& entry : byFace) {
    crossed[std::size_t(entry.first)] = 1;
    crossedFaces.push_back(entry.first);
  }
  const std::vector<int> enclosed =
      enclosedFaces(target, crossed, sideMarks(target, loop, byFace, crossed), innerLeft);
  if (crossedFaces.size() + enclosed.size() == target.n_faces())
    throw GeodesicRegionError("placement",
                              "the walked region would cover the whole target: use a smaller "
                              "scale or base");
  return {crossedFaces, enclosed};
}

// Spec 2.2 "geodesic walk" with the from_origin placement: walk, close, fill, make the canvas.
GeodesicRegionResult geodesicRegion(const MeshPtr& target, const Parameterization& base,
                                    const Parameterization& placement,
                                    const GeodesicRegionOptions& options) {
  if (!target || target->surface.n_faces() == 0)
    throw GeodesicRegionError("target", "the target mesh has no faces");
  const std::vector<Vector2d> polygon = basePolygon(base);
  requirePlacement(target, placement);
  const TriMesh& mesh = target->surface;
  const SurfacePoint start = startPoint(mesh, placement);
  const double reach =
      options.originTolerance * boundingDiagonal(placement.canvas->surface.n_vertices() > 0
                                                     ? placement.canvas->surface
                                                     : mesh);
  if (!(start.distance <= reach))
    throw GeodesicRegionError("placement", "the origin lies " + number(start.distance) +
                                               " from the target, farther than " + number(reach) +
                                               ": use the target DEM's output for this target");
  GeodesicRegionOptions walking = options;
  if (!(walking.walk.meanEdge > 0))
    walking.walk.meanEdge = meanEdgeLength(placement.canvas->surface);
  GeodesicRegionResult result;
  result.loop = walkLoop(mesh, start, placement.origin, placement.scale, polygon, walking);
  std::tie(result.crossed, result.enclosed) =
      loopFaces(mesh, result.loop, signedArea2(polygon) > 0);
  std::vector<int> faces = result.crossed;
  faces.insert(faces.end(), result.enclosed.begin(), result.enclosed.end());
  std::sort(faces.begin(), faces.end());
  // The region's origin is the walk's start, or corner 0 where the polygon leaves the start out.
  const bool holdsStart = std::binary_search(faces.begin(), faces.end(), start.face);
  const LoopPiece& first = result.loop.pieces.front();
  try {
    result.region = canvasFromFaces(target, faces, holdsStart ? start.face : first.face,
                                    holdsStart ? start.point : first.from);
  } catch (const std::invalid_argument& e) {
    throw GeodesicRegionError("placement", std::string("the walked region is not a disc: ") +
                                               e.what() +
                                               ": use a smaller scale, or move the origin where "
                                               "the target curves less");
  }
  return result;
}

}  // namespace geobrush
