// Automatic hole filling: loops, charts, and each fill joined to the mesh.
#include "fill_holes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

#include <Eigen/Geometry>

#include "geobrush/intersection.hpp"
#include "hole_membrane.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

std::string loopName(int id, const BoundaryLoop& loop) {
  return "loop " + std::to_string(id) + " (" + std::to_string(loop.vertices.size()) +
         " border edges, from vertex " + std::to_string(loop.vertices.front()) + ")";
}

// Border heights up to this fraction of the loop's length count as a plane: what rounding to the
// six or seven digits mesh files often keep leaves of one.
constexpr double kPlanarBorder = 1e-5;

// A unit vector normal to `normal`, the same for the same normal.
Vector3d perpendicular(const Vector3d& normal) {
  int smallest = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(normal[k]) < std::abs(normal[smallest])) smallest = k;
  return normal.cross(Vector3d::Unit(smallest)).normalized();
}

HoleChart chartAlong(const Vector3d& normal, const Vector3d& origin,
                     const std::vector<Vector3d>& points) {
  HoleChart chart;
  chart.origin = origin;
  chart.normal = normal;
  chart.axisU = perpendicular(normal);
  chart.axisV = normal.cross(chart.axisU);
  for (const auto& p : points)
    chart.border.push_back(chart.toChart(p));
  return chart;
}

// Passes of smoothing a folded projection may take; each moves a point at most half way to its
// neighbours' mean, so a few passes undo a zigzag and leave the loop's shape.
constexpr int kChartSmoothingPasses = 8;

std::vector<Vector2d> smoothedAlongLoop(const std::vector<Vector2d>& loop) {
  const std::size_t n = loop.size();
  std::vector<Vector2d> smoothed(n);
  for (std::size_t i = 0; i < n; ++i)
    smoothed[i] = 0.5 * loop[i] + 0.25 * (loop[(i + n - 1) % n] + loop[(i + 1) % n]);
  return smoothed;
}

double signedArea(const std::vector<Vector2d>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vector2d &a = polygon[i], &b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

// The known ring outside a hole: every existing face at a border vertex, and their vertices.
struct HoleRing {
  std::vector<std::array<int, 3>> faces;  // mesh vertex ids
  std::vector<int> outerVertices;         // ring vertices not on the loop, increasing
};

HoleRing ringAround(const TriMesh& mesh, const BoundaryLoop& loop) {
  const std::set<int> border(loop.vertices.begin(), loop.vertices.end());
  std::set<int> faces, outer;
  for (int v : loop.vertices)
    for (auto f : mesh.vf_range(TriMesh::VertexHandle(v)))
      faces.insert(f.idx());
  HoleRing ring;
  for (int f : faces) {
    std::array<int, 3> tri{};
    int k = 0;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f))) {
      tri[std::size_t(k++)] = v.idx();
      if (!border.count(v.idx())) outer.insert(v.idx());
    }
    ring.faces.push_back(tri);
  }
  ring.outerVertices.assign(outer.begin(), outer.end());
  return ring;
}

// The chord of triangle t, between two border points that the mesh already joins by an edge,
// as the corner it starts at; -1 when there is none.
int existingChord(const PlanarPatch& patch, std::size_t t, const TriMesh& mesh,
                  const BoundaryLoop& loop) {
  const int n = int(loop.vertices.size());
  for (int k = 0; k < 3; ++k) {
    const int a = patch.triangles[t][std::size_t(k)],
              b = patch.triangles[t][std::size_t((k + 1) % 3)];
    if (a >= n || b >= n || (a + 1) % n == b || (b + 1) % n == a) continue;
    if (mesh.find_halfedge(TriMesh::VertexHandle(loop.vertices[std::size_t(a)]),
                           TriMesh::VertexHandle(loop.vertices[std::size_t(b)]))
            .is_valid())
      return k;
  }
  return -1;
}

struct HoleFill {
  int continuity = 1;  // the one used: 0 for a border in a plane
  std::vector<Vector3d> newPoints;
  std::vector<std::array<int, 3>> faces;  // mesh vertex ids, new points from mesh.n_vertices()
};

// The chart's triangulation of the hole, as dense as the mesh around its border: each border
// vertex asks for the edge of an equilateral triangle as large as its faces on the surface (on
// average), so that long thin faces (a CAD part's fans) ask for their area, not their length.
PlanarPatch gradedPatch(const TriMesh& mesh, const BoundaryLoop& loop, const HoleChart& chart,
                        double density) {
  std::vector<double> size;
  for (int v : loop.vertices) {
    double area = 0.0;
    int faces = 0;
    for (auto f : mesh.vf_range(TriMesh::VertexHandle(v))) {
      area += mesh.calc_face_area(f);
      ++faces;
    }
    size.push_back(std::sqrt(4.0 / std::sqrt(3.0) * area / faces));
  }
  PlanarPatch patch = triangulatePolygon(chart.border, size, density);
  splitExistingChords(patch, mesh, loop, size);
  return patch;
}

// The membrane over a hole: its points are the patch's new ones, then the border, then the ring
// outside (`known`, mesh vertices), and its triangles the patch's (weighed in the chart) and the
// ring's (weighed by their own shape: projected, they may fold where the surface turns).
struct HoleMembrane {
  MembraneProblem problem;
  std::vector<int> known;
};

HoleMembrane holeMembrane(const TriMesh& mesh, const BoundaryLoop& loop, const PlanarPatch& patch) {
  const int n = int(loop.vertices.size()), added = int(patch.points.size()) - n;
  const HoleRing ring = ringAround(mesh, loop);
  HoleMembrane membrane;
  membrane.known = loop.vertices;
  membrane.known.insert(membrane.known.end(), ring.outerVertices.begin(), ring.outerVertices.end());
  std::unordered_map<int, int> local;  // mesh vertex -> membrane point
  for (std::size_t k = 0; k < membrane.known.size(); ++k)
    local[membrane.known[k]] = added + int(k);
  MembraneProblem& problem = membrane.problem;
  problem.pointCount = added + int(membrane.known.size());
  problem.unknownCount = added;
  problem.completeCount = added + n;
  auto membranePoint = [&](int p) { return p < n ? added + p : p - n; };
  for (const auto& tri : patch.triangles) {
    problem.triangles.push_back(
        {membranePoint(tri[0]), membranePoint(tri[1]), membranePoint(tri[2])});
    std::array<Vector3d, 3> corners;
    for (int k = 0; k < 3; ++k)
      corners[k] << patch.points[std::size_t(tri[k])], 0.0;
    problem.corners.push_back(corners);
  }
  for (const auto& face : ring.faces) {
    problem.triangles.push_back({local.at(face[0]), local.at(face[1]), local.at(face[2])});
    problem.corners.push_back(
        {pointOf(mesh, face[0]), pointOf(mesh, face[1]), pointOf(mesh, face[2])});
  }
  return membrane;
}

// The fill's new points: the harmonic membrane over the chart (heights over a plane, positions
// over a disc); for C1, the biharmonic membrane of the positions, weighed by the harmonic fill's
// own shape (as CGAL's fairing weighs by its first patch, here a smooth one).
std::vector<Vector3d> solveFill(const TriMesh& mesh, const BoundaryLoop& loop,
                                const HoleChart& chart, const PlanarPatch& patch,
                                HoleMembrane membrane, int continuity) {
  const int n = int(loop.vertices.size()), added = int(patch.points.size()) - n;
  MembraneProblem& problem = membrane.problem;
  const auto& known = membrane.known;
  problem.continuity = 0;
  problem.values = Eigen::MatrixXd::Zero(problem.pointCount, chart.planar ? 1 : 3);
  for (std::size_t k = 0; k < known.size(); ++k) {
    const Vector3d p = pointOf(mesh, known[k]);
    if (chart.planar)
      problem.values(added + int(k), 0) = chart.height(p);
    else
      problem.values.row(added + int(k)) = p.transpose();
  }
  const Eigen::MatrixXd harmonic = solveMembrane(problem);
  std::vector<Vector3d> lifted(static_cast<std::size_t>(added));
  for (int i = 0; i < added; ++i)
    lifted[std::size_t(i)] = chart.planar
                                 ? chart.toSpace(patch.points[std::size_t(n + i)], harmonic(i, 0))
                                 : Vector3d(harmonic.row(i).transpose());
  if (continuity == 0) return lifted;

  problem.continuity = 1;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int p = patch.triangles[t][std::size_t(k)];
      problem.corners[t][std::size_t(k)] =
          p < n ? pointOf(mesh, loop.vertices[std::size_t(p)]) : lifted[std::size_t(p - n)];
    }
  problem.values.resize(problem.pointCount, 3);
  for (std::size_t k = 0; k < known.size(); ++k)
    problem.values.row(added + int(k)) = pointOf(mesh, known[k]).transpose();
  const Eigen::MatrixXd positions = solveMembrane(problem);
  for (int i = 0; i < added; ++i)
    lifted[std::size_t(i)] = positions.row(i).transpose();
  return lifted;
}

HoleFill fillOne(const TriMesh& mesh, const BoundaryLoop& loop, int loopId,
                 const FillHolesOptions& options, int firstNewVertex) {
  const HoleChart chart = chartHole(mesh, loop);
  HoleFill fill;
  // A border in a plane (a cut through a CAD part) is capped flat whatever the ring's slopes.
  double borderHeight = 0.0;
  for (int v : loop.vertices)
    borderHeight = std::max(borderHeight, std::abs(chart.height(pointOf(mesh, v))));
  const bool flat = chart.planar && borderHeight <= kPlanarBorder * loop.length;
  fill.continuity = flat ? 0 : options.continuity;
  PlanarPatch patch;
  try {
    patch = gradedPatch(mesh, loop, chart, options.density);
    fill.newPoints =
        solveFill(mesh, loop, chart, patch, holeMembrane(mesh, loop, patch), fill.continuity);
  } catch (const std::runtime_error& e) {
    throw FillHolesError(loopId, loopName(loopId, loop) + ": " + e.what());
  }
  const int n = int(loop.vertices.size());
  for (const auto& tri : patch.triangles) {
    std::array<int, 3> face{};
    for (int k = 0; k < 3; ++k)
      face[std::size_t(k)] = tri[std::size_t(k)] < n
                                 ? loop.vertices[std::size_t(tri[std::size_t(k)])]
                                 : firstNewVertex + tri[std::size_t(k)] - n;
    fill.faces.push_back(face);
  }
  return fill;
}

std::vector<bool> chosenLoops(const std::vector<BoundaryLoop>& loops,
                              const FillHolesOptions& options, std::vector<HoleReport>& reports) {
  std::vector<bool> chosen(loops.size(), options.selection != HoleSelection::Listed);
  if (options.selection == HoleSelection::Listed) {
    for (int id : options.loops) {
      if (id < 0 || id >= int(loops.size()))
        throw std::invalid_argument("there is no loop " + std::to_string(id) + " (the mesh has " +
                                    std::to_string(loops.size()) + " boundary loops)");
      chosen[std::size_t(id)] = true;
    }
  }
  for (std::size_t i = 0; i < loops.size(); ++i)
    if (!chosen[i]) reports[i].leftOpen = "not chosen";
  if (options.selection == HoleSelection::AllButLargest && !loops.empty()) {
    std::size_t largest = 0;
    for (std::size_t i = 1; i < loops.size(); ++i)
      if (loops[i].length > loops[largest].length) largest = i;
    chosen[largest] = false;
    reports[largest].leftOpen = "the largest loop";
  }
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (!chosen[i] || options.maxBorderEdges <= 0 ||
        int(loops[i].vertices.size()) <= options.maxBorderEdges)
      continue;
    chosen[i] = false;
    reports[i].leftOpen = "more than " + std::to_string(options.maxBorderEdges) + " border edges";
  }
  return chosen;
}

double meanEdgeLength(const std::vector<Vector3d>& points,
                      const std::vector<std::array<int, 3>>& faces, const TriMesh& mesh,
                      int firstNewVertex) {
  std::set<std::pair<int, int>> edges;
  for (const auto& f : faces)
    for (int k = 0; k < 3; ++k)
      edges.insert(std::minmax(f[k], f[(k + 1) % 3]));
  auto at = [&](int v) {
    return v < firstNewVertex ? pointOf(mesh, v) : points[std::size_t(v - firstNewVertex)];
  };
  double sum = 0.0;
  int count = 0;
  for (const auto& [a, b] : edges) {
    if (a < firstNewVertex && b < firstNewVertex &&
        mesh.find_halfedge(TriMesh::VertexHandle(a), TriMesh::VertexHandle(b)).is_valid())
      continue;  // a border edge
    sum += (at(a) - at(b)).norm();
    ++count;
  }
  return count ? sum / count : 0.0;
}

// The face pairs each loop's fill makes with the mesh (or another fill), where it has any.
std::map<int, std::size_t> crossingFills(const TriMesh& mesh,
                                         const std::vector<std::vector<int>>& newFaces) {
  std::vector<int> all;
  for (const auto& faces : newFaces)
    all.insert(all.end(), faces.begin(), faces.end());
  std::map<int, std::size_t> crossing;
  if (all.empty()) return crossing;
  const double tolerance = 1e-9 * boundingDiagonal(mesh);
  if (selfIntersections(mesh, all, tolerance) == 0) return crossing;
  for (std::size_t i = 0; i < newFaces.size(); ++i)
    if (const std::size_t count = selfIntersections(mesh, newFaces[i], tolerance); count > 0)
      crossing[int(i)] = count;
  return crossing;
}

// Where the border's slopes fold a fill into the surface, its values alone may not: refills
// those loops harmonic, in place (the same triangulation), and returns the loops that still cut.
std::map<int, std::size_t> refillCrossingHarmonic(const TriMesh& mesh,
                                                  const std::vector<BoundaryLoop>& loops,
                                                  const FillHolesOptions& options,
                                                  const std::vector<int>& firstVertex,
                                                  const std::vector<std::vector<int>>& newFaces,
                                                  FillHolesResult& result) {
  const auto crossing = crossingFills(result.mesh, newFaces);
  if (crossing.empty()) return crossing;
  FillHolesOptions harmonic = options;
  harmonic.continuity = 0;
  for (const auto& [i, count] : crossing) {
    auto& report = result.holes[std::size_t(i)];
    if (report.continuity == 0) continue;
    const int first = firstVertex[std::size_t(i)];
    const HoleFill fill = fillOne(mesh, loops[std::size_t(i)], i, harmonic, first);
    for (std::size_t k = 0; k < fill.newPoints.size(); ++k) {
      const Vector3d& p = fill.newPoints[k];
      result.mesh.set_point(TriMesh::VertexHandle(first + int(k)), toPoint(p));
    }
    report.continuity = 0;
    report.note = "filled harmonic: with the border's slopes it cut the surface";
  }
  return crossingFills(result.mesh, newFaces);
}

}  // namespace

void splitExistingChords(PlanarPatch& patch, const TriMesh& mesh, const BoundaryLoop& loop,
                         std::vector<double>& size) {
  for (std::size_t t = 0; t < patch.triangles.size();) {
    const int k = existingChord(patch, t, mesh, loop);
    if (k < 0) {
      ++t;
      continue;
    }
    const auto tri = patch.triangles[t];
    const int a = tri[std::size_t(k)], b = tri[std::size_t((k + 1) % 3)],
              c = tri[std::size_t((k + 2) % 3)];
    const int mid = int(patch.points.size());
    patch.points.push_back(0.5 * (patch.points[std::size_t(a)] + patch.points[std::size_t(b)]));
    size.push_back(0.5 * (size[std::size_t(a)] + size[std::size_t(b)]));
    patch.triangles[t] = {a, mid, c};
    patch.triangles.push_back({mid, b, c});
    // The triangle across the chord, if any, splits too.
    for (std::size_t u = 0; u < patch.triangles.size(); ++u) {
      const auto other = patch.triangles[u];
      for (int j = 0; j < 3; ++j) {
        if (other[std::size_t(j)] != b || other[std::size_t((j + 1) % 3)] != a) continue;
        const int d = other[std::size_t((j + 2) % 3)];
        patch.triangles[u] = {b, mid, d};
        patch.triangles.push_back({mid, a, d});
        u = patch.triangles.size();  // done
        break;
      }
    }
    // Triangle t is looked at again: it may have another chord.
  }
}

Vector2d HoleChart::toChart(const Vector3d& p) const {
  return {axisU.dot(p - origin), axisV.dot(p - origin)};
}

Vector3d HoleChart::toSpace(const Vector2d& uv, double h) const {
  return origin + uv.x() * axisU + uv.y() * axisV + h * normal;
}

std::vector<BoundaryLoop> boundaryLoops(const TriMesh& mesh) {
  std::vector<bool> seen(mesh.n_halfedges(), false);
  std::vector<BoundaryLoop> loops;
  for (auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || seen[std::size_t(start.idx())]) continue;
    BoundaryLoop loop;
    auto h = start;
    do {
      seen[std::size_t(h.idx())] = true;
      loop.vertices.push_back(mesh.from_vertex_handle(h).idx());
      loop.length += mesh.calc_edge_length(h);
      h = mesh.next_halfedge_handle(h);
    } while (h != start && loop.vertices.size() <= mesh.n_halfedges());
    std::rotate(loop.vertices.begin(), std::min_element(loop.vertices.begin(), loop.vertices.end()),
                loop.vertices.end());
    loops.push_back(std::move(loop));
  }
  std::sort(loops.begin(), loops.end(), [](const BoundaryLoop& a, const BoundaryLoop& b) {
    return a.vertices.front() < b.vertices.front();
  });
  return loops;
}

HoleChart chartHole(const TriMesh& mesh, const BoundaryLoop& loop) {
  std::vector<Vector3d> points;
  Vector3d origin = Vector3d::Zero(), areaNormal = Vector3d::Zero();
  for (int v : loop.vertices)
    points.push_back(pointOf(mesh, v));
  for (std::size_t i = 0; i < points.size(); ++i) {
    origin += points[i];
    areaNormal += points[i].cross(points[(i + 1) % points.size()]);
  }
  origin /= double(points.size());
  Vector3d faceNormal = Vector3d::Zero();
  for (int v : loop.vertices)
    for (auto f : mesh.vf_range(TriMesh::VertexHandle(v))) {
      const auto n = mesh.calc_face_normal(f);
      faceNormal += Vector3d(n[0], n[1], n[2]);
    }
  for (const Vector3d& normal : {areaNormal, faceNormal}) {
    if (!(normal.norm() > 0.0)) continue;
    HoleChart chart = chartAlong(normal.normalized(), origin, points);
    if (signedArea(chart.border) > 0.0 && isSimplePolygon(chart.border)) return chart;
  }
  // A border that zigzags (along a chamfer, a scan's ragged edge) folds in projection only
  // locally: smoothed along the loop, its projection comes apart. Only the chart moves; the
  // border's vertices stay where they are.
  if (areaNormal.norm() > 0.0) {
    HoleChart chart = chartAlong(areaNormal.normalized(), origin, points);
    chart.planar = false;  // the fill's positions follow the border, not the chart
    for (int pass = 0; pass < kChartSmoothingPasses; ++pass) {
      chart.border = smoothedAlongLoop(chart.border);
      if (signedArea(chart.border) > 0.0 && isSimplePolygon(chart.border)) return chart;
    }
  }
  HoleChart disc = chartAlong(areaNormal.norm() > 0.0 ? areaNormal.normalized() : Vector3d::UnitZ(),
                              origin, points);
  disc.planar = false;
  const double radius = loop.length / (2.0 * M_PI);
  double arc = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double angle = 2.0 * M_PI * arc / loop.length;
    disc.border[i] = radius * Vector2d(std::cos(angle), std::sin(angle));
    arc += (points[(i + 1) % points.size()] - points[i]).norm();
  }
  return disc;
}

FillHolesResult fillHoles(const TriMesh& mesh, const FillHolesOptions& options) {
  if (options.continuity != 0 && options.continuity != 1)
    throw std::invalid_argument("continuity is 0 or 1");
  if (!(options.density > 0.0)) throw std::invalid_argument("density must be positive");
  const std::vector<BoundaryLoop> loops = boundaryLoops(mesh);
  FillHolesResult result;
  result.mesh = mesh;
  result.holes.resize(loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    auto& report = result.holes[i];
    report.loop = int(i);
    report.borderEdges = int(loops[i].vertices.size());
    report.borderMeanEdge = loops[i].length / double(loops[i].vertices.size());
  }
  const std::vector<bool> chosen = chosenLoops(loops, options, result.holes);
  std::vector<std::vector<int>> newFaces(loops.size());
  std::vector<int> firstVertex(loops.size(), 0);
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (!chosen[i]) continue;
    const auto start = std::chrono::steady_clock::now();
    firstVertex[i] = int(result.mesh.n_vertices());
    const HoleFill fill = fillOne(mesh, loops[i], int(i), options, firstVertex[i]);
    for (std::size_t f = 0; f < fill.faces.size(); ++f)
      newFaces[i].push_back(int(result.mesh.n_faces() + f));
    for (const auto& p : fill.newPoints)
      result.mesh.add_vertex(toPoint(p));
    for (const auto& f : fill.faces) {
      const auto face = result.mesh.add_face(
          TriMesh::VertexHandle(f[0]), TriMesh::VertexHandle(f[1]), TriMesh::VertexHandle(f[2]));
      if (!face.is_valid())
        throw FillHolesError(
            int(i), loopName(int(i), loops[i]) + ": its fill would make the mesh non-manifold");
    }
    auto& report = result.holes[i];
    report.filled = true;
    report.continuity = fill.continuity;
    report.newVertices = int(fill.newPoints.size());
    report.newFaces = int(fill.faces.size());
    report.newMeanEdge = meanEdgeLength(fill.newPoints, fill.faces, mesh, firstVertex[i]);
    report.timeMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  const auto crossing = refillCrossingHarmonic(mesh, loops, options, firstVertex, newFaces, result);
  if (!crossing.empty()) {
    const auto [i, count] = *crossing.begin();
    throw FillHolesError(
        i, loopName(i, loops[std::size_t(i)]) + ": its fill would cut through the surface (" +
               std::to_string(count) + (count == 1 ? " face pair)" : " face pairs)"));
  }
  return result;
}

}  // namespace geobrush
