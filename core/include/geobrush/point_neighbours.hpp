// The k nearest of a set of points in space (a kd-tree, nanoflann): the closest template vertex
// t_b of a border point b in surface inpainting's ICP (Freeform surface inpainting, section 4.1).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace geobrush {

class PointNeighbours {
 public:
  // Indexes `points` (copied). Throws std::invalid_argument naming the first non-finite point.
  explicit PointNeighbours(std::vector<Eigen::Vector3d> points);
  ~PointNeighbours();
  PointNeighbours(const PointNeighbours&) = delete;
  PointNeighbours& operator=(const PointNeighbours&) = delete;

  // The indices of the min(k, size) points nearest to `query`, nearest first; equal distances in
  // index order, also where they straddle the k-th place. Throws std::invalid_argument for a
  // non-finite query.
  std::vector<int> nearest(const Eigen::Vector3d& query, int k) const;
  std::size_t size() const { return points_.size(); }
  const Eigen::Vector3d& point(int index) const { return points_[std::size_t(index)]; }
  const std::vector<Eigen::Vector3d>& points() const { return points_; }

 private:
  struct Tree;
  std::vector<Eigen::Vector3d> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace geobrush
