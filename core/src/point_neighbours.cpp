#include "geobrush/point_neighbours.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace geobrush {
namespace {

// nanoflann's dataset interface over the points.
struct PointCloud {
  const std::vector<Eigen::Vector3d>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return (*points)[index][int(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

// (squared distance, index) pairs ordered by distance, then index.
using Candidates = std::vector<std::pair<double, std::uint32_t>>;

}  // namespace

struct PointNeighbours::Tree {
  using Index =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                          PointCloud, 3, std::uint32_t>;
  explicit Tree(const std::vector<Eigen::Vector3d>& points)
      : cloud{&points}, index(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    index.buildIndex();
  }

  // The `count` nearest, equal distances in nanoflann's traversal order.
  Candidates knn(const double* at, std::size_t count) const {
    std::vector<std::uint32_t> indices(count);
    std::vector<double> squared(count);
    const std::size_t found = index.knnSearch(at, count, indices.data(), squared.data());
    Candidates result;
    for (std::size_t i = 0; i < found; ++i)
      result.emplace_back(squared[i], indices[i]);
    return result;
  }

  // Every point at squared distance up to `squared`.
  Candidates within(const double* at, double squared) const {
    std::vector<std::pair<std::uint32_t, double>> found;
    const double radius = std::nextafter(squared, std::numeric_limits<double>::infinity());
    index.radiusSearch(at, radius, found, nanoflann::SearchParams(32, 0, false));
    Candidates result;
    for (const auto& [i, d] : found)
      result.emplace_back(d, i);
    return result;
  }

  PointCloud cloud;
  Index index;
};

PointNeighbours::PointNeighbours(std::vector<Eigen::Vector3d> points) : points_(std::move(points)) {
  for (std::size_t i = 0; i < points_.size(); ++i)
    if (!points_[i].allFinite())
      throw std::invalid_argument("point " + std::to_string(i) + " is not finite");
  tree_ = std::make_unique<Tree>(points_);
}

PointNeighbours::~PointNeighbours() = default;

std::vector<int> PointNeighbours::nearest(const Eigen::Vector3d& query, int k) const {
  if (!query.allFinite()) throw std::invalid_argument("the query point is not finite");
  const std::size_t count = std::min(std::size_t(std::max(k, 0)), points_.size());
  if (count == 0) return {};
  const double at[3] = {query.x(), query.y(), query.z()};
  // One more than asked shows whether a tie straddles the k-th place: nanoflann breaks such
  // ties by its traversal, so then every point as near as the k-th is gathered and ordered here.
  Candidates candidates = tree_->knn(at, std::min(count + 1, points_.size()));
  if (candidates.size() > count && candidates[count].first == candidates[count - 1].first)
    candidates = tree_->within(at, candidates[count - 1].first);
  std::sort(candidates.begin(), candidates.end());
  std::vector<int> result;
  for (std::size_t i = 0; i < count; ++i)
    result.push_back(int(candidates[i].second));
  return result;
}

}  // namespace geobrush
