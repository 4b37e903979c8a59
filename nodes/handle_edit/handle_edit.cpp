#include "handle_edit.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "geobrush/parallel.hpp"

namespace geobrush {
namespace {

// Vertices per block of the parallel loops: large enough that a block outweighs its scheduling.
constexpr std::size_t kBlock = 16384;

std::string rowText(std::size_t row) {
  std::string text = "row ";
  text += std::to_string(row + 1);
  return text;
}

HandleEdit editFromRow(std::span<const double> r, std::size_t row) {
  for (double x : r)
    if (!std::isfinite(x))
      throw HandleEditError("edits", rowText(row) + ": every number must be finite");
  HandleEdit edit;
  edit.point = {r[0], r[1], r[2]};
  edit.radius = r[3];
  edit.translation = {r[4], r[5], r[6]};
  edit.axis = {r[7], r[8], r[9]};
  edit.angleDegrees = r[10];
  if (edit.radius < 0) throw HandleEditError("edits", rowText(row) + ": the radius is negative");
  if (edit.angleDegrees != 0 && edit.axis.squaredNorm() == 0)
    throw HandleEditError("edits", rowText(row) + ": a rotation needs a non-zero axis");
  return edit;
}

// The vertex nearest `point`; the lowest index among equally near ones.
int nearestVertex(const TriMesh& mesh, const Eigen::Vector3d& point) {
  int best = 0;
  double bestSquared = std::numeric_limits<double>::infinity();
  for (int v = 0; v < int(mesh.n_vertices()); ++v) {
    const double squared = (pointOf(mesh, v) - point).squaredNorm();
    if (squared < bestSquared) {
      bestSquared = squared;
      best = v;
    }
  }
  return best;
}

// The argument of Eq. 7, with its limits where a distance is unreached: no path to H fixes the
// point (t = 1), a path to H but none to L moves it with H (t = 0).
double shapeArgument(double toHandle, double toBoundary) {
  if (toHandle == kUnreached) return 1;
  if (toBoundary == kUnreached || toHandle == 0) return 0;
  return toHandle / (toHandle + toBoundary);
}

// Moves the points by one edit's blend x_new = alpha T x + (1 - alpha) x (section 5); alpha = 0
// leaves a point untouched, so the boundary keeps its bits.
void blend(TriMesh& mesh, const HandleRegion& region, const RigidMotion& motion,
           const HandleShape& shape) {
  parallelBlocks(mesh.n_vertices(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t v = first; v < last; ++v) {
      const double alpha = shape(region.t[v]);
      if (alpha == 0) continue;
      const TriMesh::VertexHandle vh{int(v)};
      const Eigen::Vector3d x = toEigen(mesh.point(vh));
      mesh.set_point(vh, toPoint(alpha * motion(x) + (1 - alpha) * x));
    }
  });
}

// How many points differ from the template's and the largest distance between the two.
void measure(const TriMesh& unedited, const TriMesh& edited, HandleEditReport& report) {
  const std::size_t blocks = (unedited.n_vertices() + kBlock - 1) / kBlock;
  std::vector<int> moved(blocks, 0);
  std::vector<double> farthest(blocks, 0);
  parallelBlocks(unedited.n_vertices(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    const std::size_t block = first / kBlock;
    for (std::size_t v = first; v < last; ++v) {
      const TriMesh::VertexHandle vh{int(v)};
      if (unedited.point(vh) == edited.point(vh)) continue;
      ++moved[block];
      farthest[block] = std::max(farthest[block], (edited.point(vh) - unedited.point(vh)).norm());
    }
  });
  for (std::size_t b = 0; b < blocks; ++b) {
    report.verticesMoved += moved[b];
    report.maxDisplacement = std::max(report.maxDisplacement, farthest[b]);
  }
}

// Adds the non-rigid handle's field; a zero displacement (alpha = 0) leaves a point's bits.
void displace(TriMesh& mesh, const NonrigidHandleField& field) {
  parallelBlocks(mesh.n_vertices(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t v = first; v < last; ++v) {
      if (field.displacement[v].isZero(0)) continue;
      const TriMesh::VertexHandle vh{int(v)};
      mesh.set_point(vh, toPoint(toEigen(mesh.point(vh)) + field.displacement[v]));
    }
  });
}

HandleVertexMove moveFromRow(std::span<const double> r, std::size_t row) {
  for (double x : r)
    if (!std::isfinite(x))
      throw HandleEditError("nonrigid_handle", rowText(row) + ": every number must be finite");
  return {{r[0], r[1], r[2]}, {r[3], r[4], r[5]}};
}

}  // namespace

std::vector<HandleVertexMove> movesFromRows(std::span<const double> rows) {
  if (rows.size() % kMoveRowSize != 0)
    throw HandleEditError("nonrigid_handle",
                          "expected rows of 6 numbers (px, py, pz, tx, ty, tz), got " +
                              std::to_string(rows.size()) + " numbers");
  std::vector<HandleVertexMove> moves;
  for (std::size_t row = 0; row * kMoveRowSize < rows.size(); ++row)
    moves.push_back(moveFromRow(rows.subspan(row * kMoveRowSize, kMoveRowSize), row));
  return moves;
}

NonrigidHandleField nonrigidHandleField(const TriMesh& unedited, const KnnGraph& graph,
                                        const BoundaryDistances& boundary,
                                        std::span<const HandleVertexMove> moves,
                                        const HandleShape& shape) {
  NonrigidHandleField field;
  if (moves.empty()) return field;
  std::vector<Eigen::Vector3d> translation;
  for (std::size_t row = 0; row < moves.size(); ++row) {
    const int v = nearestVertex(unedited, moves[row].point);
    const double toL = boundary.toBoundary[std::size_t(v)];
    if (toL == 0 || toL == kUnreached)
      throw HandleEditError("nonrigid_handle",
                            rowText(row) + (toL == 0 ? ": the vertex is on the template's "
                                                       "boundary, which Eq. 7 keeps fixed"
                                                     : ": no path joins the vertex to the "
                                                       "template's boundary"));
    if (std::find(field.handle.begin(), field.handle.end(), v) != field.handle.end())
      throw HandleEditError("nonrigid_handle",
                            rowText(row) + ": an earlier row moves the same vertex");
    field.handle.push_back(v);
    translation.push_back(moves[row].translation);
    field.tMax += toL / double(moves.size());
  }
  GeodesicRbfOptions rbf;
  rbf.tMax = field.tMax;
  GeodesicRbfResult carried = geodesicRbf(graph, field.handle, translation, rbf);
  field.conditionNumber = carried.conditionNumber;
  std::vector<int> sorted = field.handle;
  std::sort(sorted.begin(), sorted.end());
  const std::vector<double> toHandle = graphDistances(graph, sorted);
  field.displacement = std::move(carried.displacement);
  for (std::size_t v = 0; v < field.displacement.size(); ++v) {
    const double alpha = shape(shapeArgument(toHandle[v], boundary.toBoundary[v]));
    field.displacement[v] = alpha == 0 ? Eigen::Vector3d::Zero().eval()
                                       : Eigen::Vector3d(alpha * field.displacement[v]);
  }
  // On H alpha is exactly 1, and d_h meets each translation: keep them exact.
  for (std::size_t i = 0; i < field.handle.size(); ++i)
    field.displacement[std::size_t(field.handle[i])] = translation[i];
  return field;
}

const std::vector<std::string>& handleProfileNames() {
  static const std::vector<std::string> names = {"smoothstep", "linear", "cosine", "custom"};
  return names;
}

HandleProfile parseHandleProfile(std::string_view name) {
  if (name == "smoothstep") return HandleProfile::Smoothstep;
  if (name == "linear") return HandleProfile::Linear;
  if (name == "cosine") return HandleProfile::Cosine;
  if (name == "custom") return HandleProfile::Custom;
  throw HandleEditError("profile", "unknown profile '" + std::string(name) +
                                       "' (smoothstep, linear, cosine or custom)");
}

double HandleShape::operator()(double t) const {
  if (profile != HandleProfile::Custom) return profileValue(profile, t);
  // The ends exactly: t is 0 on H and 1 on L.
  if (t <= 0) return samples.front();
  if (t >= 1) return samples.back();
  const double at = t * double(samples.size() - 1);
  const auto i = std::min(std::size_t(at), samples.size() - 2);
  const double u = at - double(i);
  return (1 - u) * samples[i] + u * samples[i + 1];
}

HandleShape customShape(std::vector<double> samples) {
  if (samples.size() < 2)
    throw HandleEditError("profile_samples",
                          "the custom profile needs at least 2 samples (alpha at t = 0 and 1)");
  for (double a : samples)
    if (!std::isfinite(a)) throw HandleEditError("profile_samples", "every sample must be finite");
  if (samples.front() != 1 || samples.back() != 0)
    throw HandleEditError("profile_samples",
                          "the custom profile must start at 1 (on the handle) and end at 0 (on "
                          "the template's boundary)");
  HandleShape shape(HandleProfile::Custom);
  shape.samples = std::move(samples);
  return shape;
}

double profileValue(HandleProfile profile, double t) {
  switch (profile) {
    case HandleProfile::Smoothstep:
      return 1 - t * t * (3 - 2 * t);
    case HandleProfile::Linear:
      return 1 - t;
    case HandleProfile::Cosine:
      // cos(pi) is -1 + 1e-16 short of exact: pin the ends so that L stays fixed.
      if (t >= 1) return 0;
      return (1 + std::cos(std::numbers::pi * t)) / 2;
    case HandleProfile::Custom:
      break;
  }
  throw std::invalid_argument("the custom profile's values come from its samples");
}

std::vector<HandleEdit> editsFromRows(std::span<const double> rows) {
  if (rows.size() % kEditRowSize != 0)
    throw HandleEditError("edits",
                          "expected rows of 11 numbers (px, py, pz, radius, tx, ty, tz, "
                          "ax, ay, az, angle_deg), got " +
                              std::to_string(rows.size()) + " numbers");
  std::vector<HandleEdit> edits;
  for (std::size_t row = 0; row * kEditRowSize < rows.size(); ++row)
    edits.push_back(editFromRow(rows.subspan(row * kEditRowSize, kEditRowSize), row));
  return edits;
}

KnnGraph vertexGraph(const TriMesh& mesh, int k) {
  if (k < 1) throw HandleEditError("k", "k must be at least 1");
  if (mesh.n_vertices() == 0) throw HandleEditError("template", "the template has no vertices");
  try {
    return KnnGraph(vertexPoints(mesh), k);
  } catch (const std::invalid_argument& e) {
    throw HandleEditError("template", e.what());
  }
}

BoundaryDistances boundaryDistances(const TriMesh& mesh, const KnnGraph& graph) {
  BoundaryDistances result;
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v)) result.boundary.push_back(v.idx());
  if (result.boundary.empty())
    throw HandleEditError("template",
                          "the template has no boundary: Eq. 7 needs one to hold the edit's "
                          "region of influence");
  result.toBoundary = graphDistances(graph, result.boundary);
  return result;
}

HandleRegion handleRegion(const TriMesh& mesh, const KnnGraph& graph,
                          const BoundaryDistances& boundary, const Eigen::Vector3d& point,
                          double radius) {
  HandleRegion region;
  region.seed = nearestVertex(mesh, point);
  const std::vector<int> seed = {region.seed};
  const std::vector<double> fromSeed = graphDistances(graph, seed, radius);
  for (int v = 0; v < int(fromSeed.size()); ++v)
    if (fromSeed[std::size_t(v)] <= radius) region.vertices.push_back(v);
  const std::vector<double> toHandle = graphDistances(graph, region.vertices);
  region.t.resize(toHandle.size());
  for (std::size_t v = 0; v < toHandle.size(); ++v)
    region.t[v] = shapeArgument(toHandle[v], boundary.toBoundary[v]);
  for (int v : region.vertices)
    region.touchesBoundary = region.touchesBoundary || boundary.toBoundary[std::size_t(v)] == 0;
  return region;
}

RigidMotion handleMotion(const HandleEdit& edit, const Eigen::Vector3d& pivot) {
  RigidMotion motion;
  if (edit.angleDegrees != 0)
    motion.rotation =
        Eigen::AngleAxisd(edit.angleDegrees * std::numbers::pi / 180, edit.axis.normalized())
            .toRotationMatrix();
  // pivot - R pivot is exactly 0 without a rotation, so a pure translation adds exactly t.
  motion.translation = edit.translation + (pivot - motion.rotation * pivot);
  return motion;
}

HandleEditReport applyHandleEdits(const TriMesh& unedited, TriMesh& mesh,
                                  std::span<const HandleRegion* const> regions,
                                  const HandleEditOptions& options,
                                  const NonrigidHandleField* nonrigid) {
  if (regions.size() != options.edits.size())
    throw std::invalid_argument("handle edit: one region per edit is needed");
  HandleEditReport report;
  for (std::size_t row = 0; row < options.edits.size(); ++row) {
    const HandleRegion& region = *regions[row];
    if (region.touchesBoundary)
      throw HandleEditError("edits", rowText(row) +
                                         ": the handle touches the template's boundary, which "
                                         "Eq. 7 keeps fixed");
    const Eigen::Vector3d pivot = pointOf(mesh, region.seed);
    blend(mesh, region, handleMotion(options.edits[row], pivot), options.profile);
    ++report.handles;
  }
  if (nonrigid && !nonrigid->handle.empty()) {
    displace(mesh, *nonrigid);
    ++report.handles;
  }
  measure(unedited, mesh, report);
  return report;
}

HandleEditResult editTemplate(const TriMesh& mesh, const HandleEditOptions& options) {
  const KnnGraph graph = vertexGraph(mesh, options.k);
  const BoundaryDistances boundary = boundaryDistances(mesh, graph);
  std::vector<HandleRegion> regions;
  for (const HandleEdit& edit : options.edits)
    regions.push_back(handleRegion(mesh, graph, boundary, edit.point, edit.radius));
  std::vector<const HandleRegion*> pointers;
  for (const HandleRegion& region : regions)
    pointers.push_back(&region);
  const NonrigidHandleField nonrigid =
      nonrigidHandleField(mesh, graph, boundary, options.nonrigid, options.profile);
  HandleEditResult result{mesh, {}};
  result.report = applyHandleEdits(mesh, result.mesh, pointers, options, &nonrigid);
  return result;
}

}  // namespace geobrush
