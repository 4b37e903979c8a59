// The k nearest of a set of points of the parameter domain (a kd-tree, nanoflann): which source
// canvas vertices a target vertex corresponds to when both are mapped into the shared (u, v)
// domain (EMD detail transfer Sec. 3.3).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string_view>
#include <vector>

namespace geobrush {

class DomainNeighbours {
 public:
  // Indexes `points` (copied); they must be finite.
  explicit DomainNeighbours(std::vector<Eigen::Vector2d> points);
  ~DomainNeighbours();
  DomainNeighbours(const DomainNeighbours&) = delete;
  DomainNeighbours& operator=(const DomainNeighbours&) = delete;

  // The indices of the min(k, size) points nearest to `query`, nearest first; equal distances in
  // index order.
  std::vector<int> nearest(const Eigen::Vector2d& query, int k) const;
  std::size_t size() const { return points_.size(); }

 private:
  struct Tree;
  std::vector<Eigen::Vector2d> points_;
  std::unique_ptr<Tree> tree_;
};

class Context;
// The neighbours among the vertices of the Parameterization on a node's input `port` (its uv),
// derived data (Context::derived): a new region searches the tree its canvas already has.
std::shared_ptr<const DomainNeighbours> derivedDomainNeighbours(Context& ctx,
                                                                std::string_view port);

}  // namespace geobrush
