#include "metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geobrush/cut_paste.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {
namespace {

Eigen::Vector3d faceNormal(const TriMesh& mesh, TriMesh::FaceHandle f) {
  const Triangle3 t = faceTriangle(mesh, f.idx());
  return (t[1] - t[0]).cross(t[2] - t[0]).normalized();
}

double mean(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

// The value below which 95% of `values` lie (nearest rank).
double percentile95(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const auto rank = std::size_t(std::ceil(0.95 * double(values.size())));
  return values[std::max<std::size_t>(rank, 1) - 1];
}

double degrees(double radians) {
  return radians * 180.0 / M_PI;
}

// Vertices with another vertex within `tolerance` of them: a seam that does not share its
// vertices shows up here.
std::vector<char> duplicatedVertices(const TriMesh& mesh, double tolerance) {
  std::vector<int> order(mesh.n_vertices());
  std::iota(order.begin(), order.end(), 0);
  auto x = [&](int v) { return mesh.point(TriMesh::VertexHandle(v))[0]; };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return x(a) < x(b); });
  std::vector<char> duplicated(mesh.n_vertices(), 0);
  for (std::size_t i = 0; i < order.size(); ++i)
    for (std::size_t j = i + 1; j < order.size() && x(order[j]) - x(order[i]) <= tolerance; ++j) {
      const auto a = TriMesh::VertexHandle(order[i]), b = TriMesh::VertexHandle(order[j]);
      if ((pointOf(mesh, a) - pointOf(mesh, b)).norm() <= tolerance)
        duplicated[std::size_t(a.idx())] = duplicated[std::size_t(b.idx())] = 1;
    }
  return duplicated;
}

// Uniform Laplacian coordinates v - mean(neighbours): rotation-invariant in magnitude, and
// comparable between a patch and its source because the paste keeps the source's connectivity.
double laplacianMagnitude(const TriMesh& mesh, TriMesh::VertexHandle v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (auto w : mesh.vv_range(v)) {
    sum += pointOf(mesh, w);
    ++count;
  }
  return count ? (pointOf(mesh, v) - sum / count).norm() : 0;
}

// Edge distance from every vertex to the nearest seam vertex, up to `limit` (limit beyond).
std::vector<int> ringsFromSeam(const TriMesh& mesh, const std::vector<int>& seamFaces, int limit) {
  std::vector<int> rings(mesh.n_vertices(), limit);
  std::vector<int> front;
  for (int f : seamFaces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      if (rings[std::size_t(v.idx())] != 0) {
        rings[std::size_t(v.idx())] = 0;
        front.push_back(v.idx());
      }
  for (int ring = 1; ring < limit && !front.empty(); ++ring) {
    std::vector<int> next;
    for (int v : front)
      for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
        if (rings[std::size_t(w.idx())] > ring) {
          rings[std::size_t(w.idx())] = ring;
          next.push_back(w.idx());
        }
    front = std::move(next);
  }
  return rings;
}

void checkMap(const TriMesh& result, const PasteMap& map, const TriMesh* target,
              const TriMesh* source) {
  if (map.targetVertex.size() != result.n_vertices() ||
      map.sourceVertex.size() != result.n_vertices())
    throw std::invalid_argument("the paste map does not describe this mesh's vertices");
  for (int f : map.seamFaces)
    if (f < 0 || std::size_t(f) >= result.n_faces())
      throw std::invalid_argument("the paste map names a seam face the mesh does not have");
  for (std::size_t v = 0; v < result.n_vertices(); ++v) {
    if (target && map.targetVertex[v] >= int(target->n_vertices()))
      throw std::invalid_argument("the paste map names a vertex the target does not have");
    if (source && map.sourceVertex[v] >= int(source->n_vertices()))
      throw std::invalid_argument("the paste map names a vertex the source canvas does not have");
  }
}

}  // namespace

std::vector<double> normalJumps(const TriMesh& mesh, const std::vector<int>& edges) {
  std::vector<double> jumps;
  for (int e : edges) {
    const auto h = mesh.halfedge_handle(TriMesh::EdgeHandle(e), 0);
    const auto f = mesh.face_handle(h), g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
    if (!f.is_valid() || !g.is_valid()) continue;
    const double c = std::clamp(faceNormal(mesh, f).dot(faceNormal(mesh, g)), -1.0, 1.0);
    jumps.push_back(std::acos(c));
  }
  return jumps;
}

PasteMetrics measurePaste(const TriMesh& result, const PasteMap* map, const TriMesh* target,
                          const TriMesh* source, const PasteMetricsOptions& options) {
  if (map) checkMap(result, *map, target, source);
  PasteMetrics m;
  auto& values = m.values;

  // Seam C0.
  const MeshStats stats = meshStats(result);
  std::size_t nonManifold = 0;
  for (auto v : result.vertices())
    nonManifold += !result.is_manifold(v);
  values["non_manifold_vertices"] = double(nonManifold);
  values["components"] = double(stats.components);
  values["boundary_loops"] = double(stats.boundaryLoops);
  values["non_finite_vertices"] = double(stats.nonFiniteVertices);
  values["manifold"] = nonManifold == 0 && stats.nonFiniteVertices == 0 ? 1 : 0;
  if (target) values["target_boundary_loops"] = double(meshStats(*target).boundaryLoops);
  const double diagonal = boundingDiagonal(result);
  const double tolerance = options.touchTolerance * diagonal;

  if (!map || map->seamFaces.empty()) {
    m.notes.push_back("no seam: the seam, the detail and new self-intersections are not measured");
    return m;
  }

  const std::vector<char> duplicated = duplicatedVertices(result, tolerance);
  std::vector<char> seamVertex(result.n_vertices(), 0);
  std::vector<int> seamEdges;
  std::vector<char> edgeListed(result.n_edges(), 0);
  for (int f : map->seamFaces)
    for (auto h : result.fh_range(TriMesh::FaceHandle(f))) {
      seamVertex[std::size_t(result.to_vertex_handle(h).idx())] = 1;
      const int e = result.edge_handle(h).idx();
      if (!edgeListed[std::size_t(e)]) seamEdges.push_back(e);
      edgeListed[std::size_t(e)] = 1;
    }
  std::size_t unshared = 0;
  for (std::size_t v = 0; v < seamVertex.size(); ++v)
    unshared += seamVertex[v] && duplicated[v];
  values["seam_unshared_vertices"] = double(unshared);

  // Seam C1: the jump of the normal across the edges of the seam strips, next to the dihedral
  // angles of the target itself around the same vertices.
  const std::vector<double> jumps = normalJumps(result, seamEdges);
  values["seam_edges"] = double(jumps.size());
  if (!jumps.empty()) {
    values["seam_normal_jump_mean_deg"] = degrees(mean(jumps));
    values["seam_normal_jump_p95_deg"] = degrees(percentile95(jumps));
  }
  if (target) {
    std::vector<char> near(target->n_vertices(), 0);
    for (std::size_t v = 0; v < seamVertex.size(); ++v)
      if (seamVertex[v] && map->targetVertex[v] >= 0) near[std::size_t(map->targetVertex[v])] = 1;
    std::vector<int> targetEdges;
    for (auto e : target->edges()) {
      const auto h = target->halfedge_handle(e, 0);
      if (near[std::size_t(target->to_vertex_handle(h).idx())] ||
          near[std::size_t(target->from_vertex_handle(h).idx())])
        targetEdges.push_back(e.idx());
    }
    const std::vector<double> own = normalJumps(*target, targetEdges);
    if (!own.empty()) {
      values["target_dihedral_mean_deg"] = degrees(mean(own));
      values["target_dihedral_p95_deg"] = degrees(percentile95(own));
    }
  } else {
    m.notes.push_back("no target connected: its own dihedral angles are not measured");
  }

  // Detail fidelity: Laplacian-coordinate magnitudes of the pasted vertices away from the seam
  // against the source canvas', after scaling by the ratio of their edge lengths.
  std::vector<int> pasted;
  for (std::size_t v = 0; v < result.n_vertices(); ++v)
    if (map->sourceVertex[v] >= 0) pasted.push_back(int(v));
  if (!source) {
    m.notes.push_back("no source connected: the detail is not measured");
  } else if (pasted.empty()) {
    m.notes.push_back("nothing was pasted: the detail is not measured");
  } else {
    double resultLength = 0, sourceLength = 0;
    for (auto e : result.edges()) {
      const auto h = result.halfedge_handle(e, 0);
      const int a = map->sourceVertex[std::size_t(result.from_vertex_handle(h).idx())];
      const int b = map->sourceVertex[std::size_t(result.to_vertex_handle(h).idx())];
      if (a < 0 || b < 0) continue;
      resultLength += result.calc_edge_length(e);
      sourceLength +=
          (pointOf(*source, TriMesh::VertexHandle(a)) - pointOf(*source, TriMesh::VertexHandle(b)))
              .norm();
    }
    const double scale = sourceLength > 0 ? resultLength / sourceLength : 1;
    values["scale_ratio"] = scale;
    if (std::abs(std::log(scale)) > std::log(1.1))
      m.notes.push_back("the paste is " + std::to_string(scale) +
                        " times the source's size: its detail is compared after scaling");
    const std::vector<int> rings = ringsFromSeam(result, map->seamFaces, options.seamBand);
    double difference = 0, reference = 0;
    std::size_t measured = 0;
    for (int v : pasted) {
      if (rings[std::size_t(v)] < options.seamBand) continue;
      const double r = laplacianMagnitude(result, TriMesh::VertexHandle(v));
      const double s =
          scale *
          laplacianMagnitude(*source, TriMesh::VertexHandle(map->sourceVertex[std::size_t(v)]));
      difference += std::abs(r - s);
      reference += s;
      ++measured;
    }
    values["detail_vertices"] = double(measured);
    if (measured == 0 || reference == 0)
      m.notes.push_back("no pasted vertex lies away from the seam: the detail is not measured");
    else
      values["detail_difference_percent"] = 100 * difference / reference;
  }

  // New self-intersections: pairs with a pasted or seam face.
  std::vector<int> newFaces = map->seamFaces;
  for (auto f : result.faces()) {
    bool fromSource = false;
    for (auto v : result.fv_range(f))
      fromSource = fromSource || map->sourceVertex[std::size_t(v.idx())] >= 0;
    if (fromSource) newFaces.push_back(f.idx());
  }
  std::sort(newFaces.begin(), newFaces.end());
  newFaces.erase(std::unique(newFaces.begin(), newFaces.end()), newFaces.end());
  values["new_self_intersections"] = double(selfIntersections(result, newFaces, tolerance));
  return m;
}

void measureAgainstReference(const TriMesh& result, const PasteMap& map, const TriMesh& reference,
                             PasteMetrics& metrics) {
  const SurfaceLocator locator(reference);
  const std::vector<Eigen::Vector3d> normals = vertexNormals(result);
  const double diagonal = boundingDiagonal(result);
  std::vector<double> distances, angles;
  for (auto v : result.vertices()) {
    if (map.targetVertex[std::size_t(v.idx())] >= 0) continue;
    const SurfacePoint nearest = locator.nearest(pointOf(result, v));
    distances.push_back(nearest.distance / diagonal);
    const double cosine =
        normals[std::size_t(v.idx())].dot(faceNormal(reference, TriMesh::FaceHandle(nearest.face)));
    angles.push_back(degrees(std::acos(std::clamp(cosine, -1.0, 1.0))));
  }
  auto& values = metrics.values;
  // The other way too: each reference vertex to the result's nearest point, so that a repair that
  // leaves out part of the truth (a smooth fill where an ear stood) does not measure as close.
  const SurfaceLocator resultLocator(result);
  std::vector<double> back;
  for (auto v : reference.vertices())
    back.push_back(resultLocator.nearest(pointOf(reference, v)).distance / diagonal);
  values["reference_to_result_mean_distance"] = mean(back);
  values["reference_to_result_max_distance"] = *std::max_element(back.begin(), back.end());
  values["reference_vertices"] = double(distances.size());
  if (distances.empty()) {
    const std::string note = "the result has no new vertex to measure against the reference";
    metrics.notes.push_back(note);
    return;
  }
  values["reference_mean_distance"] = mean(distances);
  values["reference_max_distance"] = *std::max_element(distances.begin(), distances.end());
  values["reference_normal_mean_deg"] = mean(angles);
}

std::optional<std::string> invalidPaste(const PasteMetrics& metrics) {
  const auto value = [&](const char* name) {
    const auto it = metrics.values.find(name);
    return it == metrics.values.end() ? 0.0 : it->second;
  };
  const auto count = [](double n, const char* what) {
    return std::to_string(std::llround(n)) + " " + what;
  };
  std::string problems;
  const auto add = [&](const std::string& problem) {
    problems += (problems.empty() ? "" : ", ") + problem;
  };
  if (value("non_manifold_vertices") > 0)
    add(count(value("non_manifold_vertices"), "non-manifold vertices"));
  else if (metrics.values.contains("manifold") && value("manifold") != 1)
    add("a non-manifold or non-finite result");
  if (metrics.values.contains("target_boundary_loops") &&
      value("boundary_loops") > value("target_boundary_loops"))
    add(count(value("boundary_loops") - value("target_boundary_loops"),
              "more boundary loops than the target"));
  if (value("new_self_intersections") > 0)
    add(count(value("new_self_intersections"), "new self-intersections"));
  if (problems.empty()) return std::nullopt;
  return "the paste has " + problems;
}

}  // namespace geobrush
