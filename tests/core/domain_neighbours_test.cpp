#include "geobrush/domain_neighbours.hpp"

#include <gtest/gtest.h>

#include "direct_context.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/derived_store.hpp"
#include "geobrush/registry.hpp"

namespace geobrush {
namespace {

// The points of a unit lattice, row by row.
std::vector<Eigen::Vector2d> lattice(int side) {
  std::vector<Eigen::Vector2d> points;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      points.emplace_back(x, y);
  return points;
}

// On a lattice the nearest point is the one under the query, then its four neighbours at distance
// 1, which tie and come in index order; k past the size gives every point.
TEST(DomainNeighbours, FindsTheNearestLatticePointsTiesInIndexOrder) {
  const DomainNeighbours neighbours(lattice(5));
  ASSERT_EQ(neighbours.size(), 25u);
  EXPECT_EQ(neighbours.nearest({2.1, 1.9}, 1), std::vector<int>{12});
  EXPECT_EQ(neighbours.nearest({2, 2}, 5), (std::vector<int>{12, 7, 11, 13, 17}));
  EXPECT_EQ(neighbours.nearest({-3, -3}, 100).size(), 25u);
}

// Derived from a node's input: one tree per parameterization value, shared by later computes.
TEST(DomainNeighbours, AreDerivedOncePerParameterization) {
  const NodeType reader = NodeTypeBuilder("test.reader", 1)
                              .input<Parameterization>("source", "E_s.")
                              .compute([](Context&) {})
                              .build();
  auto source = std::make_shared<Parameterization>();
  source->uv = lattice(4);
  auto other = std::make_shared<Parameterization>();
  other->uv = lattice(3);
  auto store = std::make_shared<DerivedStore>();
  std::shared_ptr<const DomainNeighbours> first;
  for (int run = 0; run < 2; ++run) {
    test::DirectContext ctx(reader, {{"source", source}}, {}, store);
    const auto found = derivedDomainNeighbours(ctx, "source");
    ASSERT_EQ(found->size(), 16u);
    if (first) {
      EXPECT_EQ(found, first);
    }
    first = found;
  }
  test::DirectContext ctx(reader, {{"source", other}}, {}, store);
  EXPECT_EQ(derivedDomainNeighbours(ctx, "source")->size(), 9u);
  EXPECT_EQ(store->builds(), 2u);
}

}  // namespace
}  // namespace geobrush
