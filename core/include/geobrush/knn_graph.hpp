// The symmetric k-nearest-neighbour graph of a point set and shortest paths along it: the
// geodesic distance delta of surface inpainting (Freeform surface inpainting, section 5.1). The
// paper's "BFS" is exact only for unit weights; edges here weigh their Euclidean length and paths
// are found by Dijkstra's algorithm.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace geobrush {

struct KnnEdge {
  int to = 0;
  double length = 0;
};

class KnnGraph {
 public:
  // Joins p and q when either is among the other's k nearest (a kd-tree, nanoflann); coincident
  // points are joined by edges of length 0. Throws std::invalid_argument for k < 1 or a
  // non-finite point.
  KnnGraph(std::span<const Eigen::Vector3d> points, int k);

  int size() const { return int(offsets_.size()) - 1; }
  int k() const { return k_; }
  // v's neighbours in increasing index order.
  std::span<const KnnEdge> neighbours(int v) const {
    return {edges_.data() + offsets_[std::size_t(v)], edges_.data() + offsets_[std::size_t(v) + 1]};
  }
  std::size_t edgeCount() const { return edges_.size() / 2; }

 private:
  int k_ = 0;
  std::vector<std::size_t> offsets_;  // CSR: neighbours of v at [offsets_[v], offsets_[v + 1])
  std::vector<KnnEdge> edges_;
};

class Context;
// The graph of the vertices of the Mesh on input `port`, derived by the framework once per mesh
// and k (Context::derived) and shared by every node that asks. Throws NodeError on the port for a
// mesh without vertices or with a point that is not finite.
std::shared_ptr<const KnnGraph> derivedVertexGraph(Context& ctx, std::string_view port, int k);

inline constexpr double kUnreached = std::numeric_limits<double>::infinity();

// Each point's graph distance to the nearest of `sources` (each at distance 0), Dijkstra's
// algorithm; points farther than `maxDistance` (or in other components) stay kUnreached, and
// the search never visits them, so its cost follows the ball it explores.
std::vector<double> graphDistances(const KnnGraph& graph, std::span<const int> sources,
                                   double maxDistance = kUnreached);

}  // namespace geobrush
