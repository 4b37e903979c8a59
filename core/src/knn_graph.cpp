#include "geobrush/knn_graph.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <stdexcept>
#include <utility>

#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"

namespace geobrush {
namespace {

// nanoflann's dataset interface over the points.
struct Cloud {
  std::span<const Eigen::Vector3d> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const { return points[index][int(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using CloudTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                      Cloud, 3, std::uint32_t>;

// Each point's k nearest others, as directed pairs (both orders added, so the graph is symmetric).
std::vector<std::pair<int, int>> nearestPairs(std::span<const Eigen::Vector3d> points, int k) {
  const Cloud cloud{points};
  CloudTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  const std::size_t wanted = std::min(std::size_t(k) + 1, points.size());
  std::vector<std::uint32_t> found(wanted);
  std::vector<double> squared(wanted);
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(2 * points.size() * std::size_t(k));
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double at[3] = {points[p].x(), points[p].y(), points[p].z()};
    const std::size_t count = tree.knnSearch(at, wanted, found.data(), squared.data());
    int taken = 0;
    for (std::size_t i = 0; i < count && taken < k; ++i) {
      if (found[i] == p) continue;
      pairs.emplace_back(int(p), int(found[i]));
      pairs.emplace_back(int(found[i]), int(p));
      ++taken;
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace

KnnGraph::KnnGraph(std::span<const Eigen::Vector3d> points, int k) : k_(k) {
  if (k < 1) throw std::invalid_argument("kNN graph: k must be at least 1");
  for (const auto& p : points)
    if (!p.allFinite()) throw std::invalid_argument("kNN graph: a point is not finite");
  const auto pairs = nearestPairs(points, k);
  offsets_.assign(points.size() + 1, 0);
  for (const auto& [from, to] : pairs)
    ++offsets_[std::size_t(from) + 1];
  for (std::size_t v = 0; v < points.size(); ++v)
    offsets_[v + 1] += offsets_[v];
  edges_.reserve(pairs.size());
  for (const auto& [from, to] : pairs)
    edges_.push_back({to, (points[std::size_t(from)] - points[std::size_t(to)]).norm()});
}

std::vector<double> graphDistances(const KnnGraph& graph, std::span<const int> sources,
                                   double maxDistance) {
  std::vector<double> distance(std::size_t(graph.size()), kUnreached);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (int s : sources) {
    if (s < 0 || s >= graph.size()) throw std::out_of_range("kNN graph: a source is no point");
    distance[std::size_t(s)] = 0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[std::size_t(v)]) continue;
    for (const KnnEdge& e : graph.neighbours(v)) {
      const double through = d + e.length;
      if (through > maxDistance || through >= distance[std::size_t(e.to)]) continue;
      distance[std::size_t(e.to)] = through;
      queue.emplace(through, e.to);
    }
  }
  return distance;
}

std::shared_ptr<const KnnGraph> derivedVertexGraph(Context& ctx, std::string_view port, int k) {
  const auto mesh = ctx.in<Mesh>(port);
  if (mesh->surface.n_vertices() == 0) throw NodeError::input(port, "the mesh has no vertices");
  return ctx.derived("knn_graph", {port}, Hasher().u64(std::uint64_t(k)).digest(), [&] {
    try {
      return std::make_shared<const KnnGraph>(vertexPoints(mesh->surface), k);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input(port, e.what());
    }
  });
}

}  // namespace geobrush
