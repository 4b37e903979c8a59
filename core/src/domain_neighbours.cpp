#include "geobrush/domain_neighbours.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <numeric>

#include "geobrush/canvas.hpp"
#include "geobrush/node.hpp"

namespace geobrush {

// nanoflann's dataset interface over the points.
struct PointSet {
  const std::vector<Eigen::Vector2d>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return (*points)[index][int(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

struct DomainNeighbours::Tree {
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>,
                                                    PointSet, 2, std::uint32_t>;
  explicit Tree(const std::vector<Eigen::Vector2d>& points)
      : set{&points}, index(2, set, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    index.buildIndex();
  }
  PointSet set;
  Index index;
};

DomainNeighbours::DomainNeighbours(std::vector<Eigen::Vector2d> points)
    : points_(std::move(points)), tree_(std::make_unique<Tree>(points_)) {}

DomainNeighbours::~DomainNeighbours() = default;

std::vector<int> DomainNeighbours::nearest(const Eigen::Vector2d& query, int k) const {
  const std::size_t count = std::min(std::size_t(std::max(k, 0)), points_.size());
  if (count == 0) return {};
  std::vector<std::uint32_t> indices(count);
  std::vector<double> distances(count);
  const double at[2] = {query.x(), query.y()};
  const std::size_t found = tree_->index.knnSearch(at, count, indices.data(), distances.data());
  std::vector<int> order(found);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return distances[std::size_t(a)] != distances[std::size_t(b)]
               ? distances[std::size_t(a)] < distances[std::size_t(b)]
               : indices[std::size_t(a)] < indices[std::size_t(b)];
  });
  std::vector<int> result;
  for (int i : order)
    result.push_back(int(indices[std::size_t(i)]));
  return result;
}

std::shared_ptr<const DomainNeighbours> derivedDomainNeighbours(Context& ctx,
                                                                std::string_view port) {
  const auto canvas = ctx.in<Parameterization>(port);
  return ctx.derived("domain_neighbours", {port}, 0,
                     [&] { return std::make_shared<const DomainNeighbours>(canvas->uv); });
}

}  // namespace geobrush
