// trianglesOverlapAlong: overlap of two triangles seen along a direction, against configurations
// in a plane whose common areas are known.
#include "geobrush/intersection.hpp"

#include <gtest/gtest.h>

namespace geobrush {
namespace {

using Eigen::Vector3d;

const Vector3d up(0, 0, 1);

Triangle3 raised(Triangle3 t, double z) {
  for (Vector3d& p : t)
    p.z() += z;
  return t;
}

TEST(TrianglesOverlapAlong, TrianglesOnEitherSideOfASharedEdgeOnlyTouch) {
  const Triangle3 below{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, -1, 0)};
  const Triangle3 above{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0)};
  EXPECT_FALSE(trianglesOverlapAlong(up, below, above));
  // Folded over the edge onto the same side, they cover half of the smaller one.
  const Triangle3 folded{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(1, 1, 0.3)};
  EXPECT_TRUE(trianglesOverlapAlong(up, above, folded));
}

TEST(TrianglesOverlapAlong, TrianglesAtASharedCornerOverlapWhereTheirAnglesDo) {
  const Triangle3 a{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(1, 1, 0)};
  const Triangle3 apart{Vector3d(0, 0, 0), Vector3d(1, 1, 0), Vector3d(0, 1, 0)};
  const Triangle3 across{Vector3d(0, 0, 0), Vector3d(1, 0.5, 0), Vector3d(0, 1, 0)};
  EXPECT_FALSE(trianglesOverlapAlong(up, a, apart));
  EXPECT_TRUE(trianglesOverlapAlong(up, a, across));
  EXPECT_TRUE(trianglesOverlapAlong(up, across, a));  // symmetric
}

TEST(TrianglesOverlapAlong, HeightAlongTheDirectionDoesNotPartThem) {
  const Triangle3 t{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0)};
  EXPECT_TRUE(trianglesOverlapAlong(up, t, raised(t, 5)));
  // Seen along x, the same two are edges on: no area.
  EXPECT_FALSE(trianglesOverlapAlong(Vector3d(1, 0, 0), t, raised(t, 5)));
  // Either winding.
  EXPECT_TRUE(trianglesOverlapAlong(up, t, Triangle3{t[0], t[2], t[1]}));
}

TEST(TrianglesOverlapAlong, ACommonAreaBelowTheShareIsASliver) {
  // The square's lower-left half against its upper-right half reaching e past the diagonal: the
  // common area, a strip about e wide along the diagonal, is about 2e of either.
  const Triangle3 half{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0)};
  const double e = 1e-7;
  const Triangle3 past{Vector3d(1 - e, 0, 0), Vector3d(1, 1, 0), Vector3d(0, 1 - e, 0)};
  EXPECT_FALSE(trianglesOverlapAlong(up, half, past, 1e-6));
  EXPECT_TRUE(trianglesOverlapAlong(up, half, past, 1e-9));
  EXPECT_FALSE(trianglesOverlapAlong(up, half, Triangle3{half[1], Vector3d(1, 1, 0), half[2]}));
}

TEST(TrianglesOverlapAlong, DegenerateTrianglesNeverOverlap) {
  const Triangle3 t{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0)};
  const Triangle3 flat{Vector3d(0, 0, 0), Vector3d(1, 1, 0), Vector3d(2, 2, 0)};
  EXPECT_FALSE(trianglesOverlapAlong(up, t, flat));
  EXPECT_FALSE(trianglesOverlapAlong(Vector3d::Zero(), t, t));
}

}  // namespace
}  // namespace geobrush
