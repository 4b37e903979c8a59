#include "fragment_complete.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "geobrush/parallel.hpp"
#include "geobrush/point_neighbours.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Points = std::vector<Vector3d>;

// Where a descriptor samples, in its tangent plane: the top layer's res^2 cell centres, then the
// bottom layer's (res / 2)^2 over the same square (section 6: "half the resolution").
struct Layout {
  std::vector<Vector2d> offsets;
  int topCells = 0;
  double maxGap = 0;  // a cell farther than this from every vertex lies off the surface
};

void addGrid(std::vector<Vector2d>& offsets, int res, double radius) {
  const double cell = 2 * radius / res;
  for (int j = 0; j < res; ++j)
    for (int i = 0; i < res; ++i)
      offsets.emplace_back(-radius + (i + 0.5) * cell, -radius + (j + 0.5) * cell);
}

Layout descriptorLayout(int res, double radius, double edge) {
  Layout layout;
  addGrid(layout.offsets, res, radius);
  layout.topCells = int(layout.offsets.size());
  addGrid(layout.offsets, std::max(1, res / 2), radius);
  layout.maxGap = 1.5 * edge;
  return layout;
}

// A tangent frame at a normal: the first axis is the coordinate axis least aligned with n
// (lowest index on ties) projected onto the tangent plane, then turned by `angle` about n.
std::pair<Vector3d, Vector3d> tangentAxes(const Vector3d& n, double angle) {
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) < std::abs(n[axis])) axis = k;
  Vector3d t1 = Vector3d::Unit(axis) - n[axis] * n;
  t1.normalize();
  const Vector3d t2 = n.cross(t1);
  return {std::cos(angle) * t1 + std::sin(angle) * t2,
          -std::sin(angle) * t1 + std::cos(angle) * t2};
}

// One level's data for the search (section 6): the completed base P^(l+1), its normals and
// kd-tree, the level's detail per vertex (the original's, the guidance's where not yet known).
struct Level {
  const Points& base;
  const Points& normal;
  const PointNeighbours& tree;
  std::vector<double> detail;
  std::vector<std::uint8_t> known;  // original, or completed on this level
  const std::vector<std::uint8_t>& original;
  bool coarsest = false;  // the base off the original surface is the guidance itself
};

// The vertex under each cell of the descriptor at `centre` turned by `angle`; -1 off the surface.
void cellVertices(const Level& level, int centre, double angle, const Layout& layout,
                  std::vector<int>& out) {
  const Vector3d& p = level.base[std::size_t(centre)];
  const auto [t1, t2] = tangentAxes(level.normal[std::size_t(centre)], angle);
  out.clear();
  for (const Vector2d& o : layout.offsets) {
    const Vector3d at = p + o.x() * t1 + o.y() * t2;
    const int w = level.tree.nearest(at, 1).front();
    out.push_back((level.base[std::size_t(w)] - at).norm() <= layout.maxGap ? w : -1);
  }
}

// A cell's value: the detail on the top layer, on the bottom the base's height over the
// centre's tangent plane (level l + 1's geometry, section 6's two-layer descriptor).
double cellValue(const Level& level, const Layout& layout, int centre, int cell, int w) {
  if (cell < layout.topCells) return level.detail[std::size_t(w)];
  const auto c = std::size_t(centre);
  return (level.base[std::size_t(w)] - level.base[c]).dot(level.normal[c]);
}

// The candidates' descriptors (vertex, rotation), flattened; only those whose every cell lies on
// original surface.
struct Candidates {
  std::vector<int> vertex;
  std::vector<float> values;  // cells per candidate
  int cells = 0;
  std::size_t count() const { return vertex.size(); }
};

// Fills slot's values; false when a cell leaves the original surface.
bool candidateDescriptor(const Level& level, const Layout& layout, int c, double angle,
                         std::vector<int>& cells, float* values) {
  cellVertices(level, c, angle, layout, cells);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (cells[k] < 0 || !level.original[std::size_t(cells[k])]) return false;
    values[k] = float(cellValue(level, layout, c, int(k), cells[k]));
  }
  return true;
}

Candidates candidateDescriptors(const Level& level, const Layout& layout,
                                const std::vector<int>& vertices, int rotations, int threads) {
  const auto cells = layout.offsets.size();
  const std::size_t slots = vertices.size() * std::size_t(rotations);
  std::vector<float> values(slots * cells);
  std::vector<std::uint8_t> valid(slots, 0);
  parallelBlocks(vertices.size(), 64, threads, [&](std::size_t first, std::size_t last) {
    std::vector<int> scratch;
    for (std::size_t i = first; i < last; ++i)
      for (int r = 0; r < rotations; ++r) {
        const std::size_t slot = i * std::size_t(rotations) + std::size_t(r);
        const double angle = 2 * std::numbers::pi * r / rotations;
        valid[slot] = candidateDescriptor(level, layout, vertices[i], angle, scratch,
                                          values.data() + slot * cells);
      }
  });
  Candidates result;
  result.cells = int(cells);
  for (std::size_t slot = 0; slot < slots; ++slot)
    if (valid[slot]) {
      result.vertex.push_back(vertices[slot / std::size_t(rotations)]);
      result.values.insert(result.values.end(), values.begin() + std::ptrdiff_t(slot * cells),
                           values.begin() + std::ptrdiff_t((slot + 1) * cells));
    }
  return result;
}

struct TargetCell {
  int cell = 0;
  double value = 0;
  double weight = 0;
};

// The descriptor of the vertex being completed: known cells weigh 1, the guidance's guidanceWeight
// (constant across levels, section 6); cells off the surface are left out.
std::vector<TargetCell> targetDescriptor(const Level& level, const Layout& layout, int v,
                                         double guidanceWeight, std::vector<int>& cells) {
  cellVertices(level, v, 0, layout, cells);
  std::vector<TargetCell> out;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const int w = cells[k];
    if (w < 0) continue;
    const bool top = int(k) < layout.topCells;
    const bool known =
        top ? level.known[std::size_t(w)] : !level.coarsest || level.original[std::size_t(w)];
    const double weight = known ? 1.0 : guidanceWeight;
    if (weight > 0) out.push_back({int(k), cellValue(level, layout, v, int(k), w), weight});
  }
  return out;
}

// The candidate of least weighted mean squared difference over the target's cells (SSD over
// valid cells), first on ties; {-1, +inf} when the target has no weight.
std::pair<int, double> bestCandidate(const Candidates& candidates,
                                     const std::vector<TargetCell>& target) {
  double total = 0;
  for (const auto& t : target)
    total += t.weight;
  if (!(total > 0)) return {-1, std::numeric_limits<double>::infinity()};
  int best = -1;
  double bestSum = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < candidates.count(); ++c) {
    const float* values = candidates.values.data() + c * std::size_t(candidates.cells);
    double sum = 0;
    for (const auto& t : target) {
      const double d = double(values[t.cell]) - t.value;
      sum += t.weight * d * d;
      if (sum >= bestSum) break;
    }
    if (sum < bestSum) {
      bestSum = sum;
      best = int(c);
    }
  }
  return {best, bestSum / total};
}

// Level l's detail: P^l's height over P^(l+1) along P^(l+1)'s normals.
std::vector<double> detailOf(const Points& fine, const Points& base, const Points& normal) {
  std::vector<double> d(fine.size());
  for (std::size_t v = 0; v < fine.size(); ++v)
    d[v] = (fine[v] - base[v]).dot(normal[v]);
  return d;
}

// One smoothing step p <- p + (mean of the one-ring - p) / 2 (uniform Laplacian).
Points smoothStep(const TriMesh& mesh, const Points& p) {
  Points out = p;
  for (auto v : mesh.vertices()) {
    Vector3d sum = Vector3d::Zero();
    int count = 0;
    for (auto w : mesh.vv_range(v)) {
      sum += p[std::size_t(w.idx())];
      ++count;
    }
    if (count > 0) out[std::size_t(v.idx())] = 0.5 * (p[std::size_t(v.idx())] + sum / count);
  }
  return out;
}

}  // namespace

std::vector<std::vector<Vector3d>> scaleSpace(const TriMesh& mesh, int levels) {
  std::vector<Points> space(1);
  for (auto v : mesh.vertices())
    space[0].push_back(pointOf(mesh, v));
  Points current = space[0];
  long long steps = 0;
  for (int l = 1; l <= levels; ++l) {
    for (const long long target = 1LL << (2 * l); steps < target; ++steps)
      current = smoothStep(mesh, current);
    space.push_back(current);
  }
  return space;
}

std::vector<Vector3d> areaWeightedNormals(const TriMesh& mesh,
                                          const std::vector<Vector3d>& points) {
  Points sum(points.size(), Vector3d::Zero());
  for (auto f : mesh.faces()) {
    int c[3], k = 0;
    for (auto v : mesh.fv_range(f))
      c[k++] = v.idx();
    const Vector3d n = (points[std::size_t(c[1])] - points[std::size_t(c[0])])
                           .cross(points[std::size_t(c[2])] - points[std::size_t(c[0])]);
    for (int i : c)
      sum[std::size_t(i)] += n;
  }
  for (auto& n : sum)
    if (n.norm() > 0) n.normalize();
  return sum;
}

std::vector<int> rimInwardOrder(const TriMesh& mesh, const std::vector<std::uint8_t>& original) {
  const std::size_t n = mesh.n_vertices();
  std::vector<int> ring(n, -1);
  std::vector<int> frontier;
  for (std::size_t v = 0; v < n; ++v)
    if (original[v]) ring[v] = 0, frontier.push_back(int(v));
  std::vector<int> order;
  for (int r = 1; !frontier.empty(); ++r) {
    std::vector<int> next;
    for (int v : frontier)
      for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
        if (ring[std::size_t(w.idx())] < 0) ring[std::size_t(w.idx())] = r, next.push_back(w.idx());
    std::sort(next.begin(), next.end());
    order.insert(order.end(), next.begin(), next.end());
    frontier = std::move(next);
  }
  for (std::size_t v = 0; v < n; ++v)
    if (ring[v] < 0) order.push_back(int(v));
  return order;
}

double completedConfidence(double cost, double edge) {
  if (!std::isfinite(cost) || !(edge > 0)) return 0;
  return kCompletedConfidence * std::exp(-std::sqrt(std::max(cost, 0.0)) / edge);
}

namespace {

// A number as messages print it.
std::string text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return buffer;
}

void checkParams(const FragmentCompleteOptions& o) {
  if (o.levels < 1 || o.levels > 6)
    throw FragmentCompleteError("levels", "levels must be 1 to 6, got " + text(o.levels));
  if (o.descRes < 2 || o.descRes > 64)
    throw FragmentCompleteError("desc_res", "desc_res must be 2 to 64, got " + text(o.descRes));
  if (!std::isfinite(o.radius) || o.radius < 0)
    throw FragmentCompleteError("radius", "radius must be finite and >= 0");
  if (o.rotations < 1 || o.rotations > 360)
    throw FragmentCompleteError("rotations", "rotations must be 1 to 360");
  if (!std::isfinite(o.guidanceWeight) || o.guidanceWeight < 0)
    throw FragmentCompleteError("guidance_weight", "guidance_weight must be finite and >= 0");
  if (o.candidateStride < 1)
    throw FragmentCompleteError("candidate_stride", "candidate_stride must be at least 1");
}

void checkInputs(const TriMesh& mesh, const std::vector<std::uint8_t>& original) {
  if (mesh.n_faces() == 0) throw FragmentCompleteError("mesh", "the mesh has no faces");
  for (auto v : mesh.vertices())
    if (!pointOf(mesh, v).allFinite()) {
      std::string message = "vertex " + std::to_string(v.idx());
      throw FragmentCompleteError("mesh", message + " is not finite");
    }
  if (original.size() != mesh.n_vertices()) {
    std::string message = "the paste map maps " + std::to_string(original.size());
    throw FragmentCompleteError(
        "paste_map", message + " vertices, the mesh has " + std::to_string(mesh.n_vertices()));
  }
  if (std::none_of(original.begin(), original.end(), [](std::uint8_t o) { return o != 0; }))
    throw FragmentCompleteError("paste_map", "no vertex is original: nothing to copy detail from");
}

// Refuses what would run for minutes: the search compares every completed vertex with every
// candidate descriptor on every level, and holds one level's candidate descriptors at once.
void checkWork(const FragmentCompleteOptions& o, std::size_t completed, std::size_t candidates,
               int cells) {
  const double stored = double(candidates) * o.rotations * cells;
  const double work = double(o.levels) * double(completed) * stored;
  if (work <= o.maxWork && stored <= o.maxStored) return;
  std::string message = "levels x completed x candidates x rotations x cells = " + text(work);
  throw FragmentCompleteError(
      "candidate_stride", message + " (limit " + text(o.maxWork) +
                              "), candidate descriptor values " + text(stored) + " (limit " +
                              text(o.maxStored) +
                              "): raise candidate_stride or lower rotations, desc_res or levels");
}

// What every level shares.
struct Job {
  const TriMesh& mesh;
  const std::vector<std::uint8_t>& original;
  std::vector<int> order;       // the vertices to complete, rim inward
  std::vector<int> candidates;  // original vertices, every stride-th
  Layout layout;
  const FragmentCompleteOptions& options;
};

// Section 6 on one level: completes P^l over the completed base P^(l+1), adding each completed
// vertex's best cost to `cost`; returns the completed P^l and the number of candidates.
std::pair<Points, std::size_t> completeLevel(const Job& job, const Points& inputFine,
                                             const Points& inputBase, const Points& base,
                                             bool coarsest, std::vector<double>& cost) {
  const Points normal = areaWeightedNormals(job.mesh, base);
  const PointNeighbours tree(base);
  auto detail = detailOf(inputFine, inputBase, areaWeightedNormals(job.mesh, inputBase));
  Level level{base, normal, tree, std::move(detail), job.original, job.original, coarsest};
  const Candidates candidates = candidateDescriptors(level, job.layout, job.candidates,
                                                     job.options.rotations, job.options.threads);
  if (candidates.count() == 0)
    throw FragmentCompleteError("radius",
                                "no candidate's descriptor lies wholly on original surface: "
                                "lower radius or candidate_stride");
  Points out = inputFine;
  std::vector<int> cells;
  for (int v : job.order) {
    const auto target = targetDescriptor(level, job.layout, v, job.options.guidanceWeight, cells);
    const auto [best, bestCost] = bestCandidate(candidates, target);
    const auto i = std::size_t(v);
    if (best >= 0)
      level.detail[i] = level.detail[std::size_t(candidates.vertex[std::size_t(best)])];
    level.known[i] = 1;
    out[i] = base[i] + level.detail[i] * normal[i];
    cost[i] += bestCost;
  }
  return {std::move(out), candidates.count()};
}

std::vector<int> candidateVertices(const std::vector<std::uint8_t>& original, int stride) {
  std::vector<int> out;
  std::size_t seen = 0;
  for (std::size_t v = 0; v < original.size(); ++v)
    if (original[v] && seen++ % std::size_t(stride) == 0) out.push_back(int(v));
  return out;
}

}  // namespace

FragmentCompleteResult fragmentComplete(const TriMesh& mesh,
                                        const std::vector<std::uint8_t>& original,
                                        const FragmentCompleteOptions& options) {
  checkParams(options);
  checkInputs(mesh, original);
  const double edge = meanEdgeLength(mesh);
  FragmentCompleteResult result;
  result.radius = options.radius > 0 ? options.radius : 4 * edge;
  if (!(result.radius > 0)) throw FragmentCompleteError("mesh", "the mesh's edges have no length");
  Job job{mesh,
          original,
          rimInwardOrder(mesh, original),
          candidateVertices(original, options.candidateStride),
          descriptorLayout(options.descRes, result.radius, edge),
          options};
  checkWork(options, job.order.size(), job.candidates.size(), int(job.layout.offsets.size()));
  result.mesh = mesh;
  result.confidence.assign(mesh.n_vertices(), 1.0);
  result.completed = job.order.size();
  if (job.order.empty()) return result;
  const auto space = scaleSpace(mesh, options.levels);
  std::vector<double> cost(mesh.n_vertices(), 0.0);
  Points completed = space[std::size_t(options.levels)];  // the guidance is the coarsest base
  for (int l = options.levels - 1; l >= 0; --l) {
    const auto li = std::size_t(l);
    auto [fine, count] =
        completeLevel(job, space[li], space[li + 1], completed, l == options.levels - 1, cost);
    completed = std::move(fine);
    result.candidates = count;
  }
  double sum = 0;
  std::size_t matched = 0;
  for (int v : job.order) {
    const auto i = std::size_t(v);
    result.mesh.set_point(TriMesh::VertexHandle(v), toPoint(completed[i]));
    result.confidence[i] = completedConfidence(cost[i] / options.levels, edge);
    if (std::isfinite(cost[i])) sum += cost[i], ++matched;
  }
  result.meanBestCost = matched ? sum / (double(matched) * options.levels) : 0;
  return result;
}

}  // namespace geobrush
