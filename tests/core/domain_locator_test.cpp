// DomainLocator: E^-1(u) and the local frame on a parameterized canvas.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "geobrush/domain_locator.hpp"

using namespace geobrush;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// The plane z = 2x + 1 over [0, 4]^2 with 4x4 quads, uv = (x, y).
Parameterization tiltedPlane() {
  auto canvas = std::make_shared<Canvas>();
  TriMesh& mesh = canvas->surface;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i)
      mesh.add_vertex({double(i), double(j), 2.0 * i + 1});
  auto vh = [](int i, int j) { return TriMesh::VertexHandle(j * 5 + i); };
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      mesh.add_face(vh(i, j), vh(i + 1, j), vh(i + 1, j + 1));
      mesh.add_face(vh(i, j), vh(i + 1, j + 1), vh(i, j + 1));
    }
  Parameterization param;
  param.canvas = canvas;
  const Vector3d normal = Vector3d(-2, 0, 1).normalized();
  for (auto v : mesh.vertices()) {
    param.uv.emplace_back(mesh.point(v)[0], mesh.point(v)[1]);
    param.normal.push_back(normal);
  }
  return param;
}

}  // namespace

TEST(DomainLocator, InverseMapAndJacobianOnAPlane) {
  const Parameterization param = tiltedPlane();
  const DomainLocator locator(param);
  for (const Vector2d& u :
       {Vector2d(0.3, 0.7), Vector2d(2.5, 3.99), Vector2d(4, 4), Vector2d(0, 0)}) {
    const DomainHit hit = locator.locate(u);
    EXPECT_TRUE(hit.inside);
    EXPECT_NEAR((hit.point - Vector3d(u.x(), u.y(), 2 * u.x() + 1)).norm(), 0, 1e-12);
    EXPECT_NEAR((hit.jacobian.col(0) - Vector3d(1, 0, 2)).norm(), 0, 1e-12);
    EXPECT_NEAR((hit.jacobian.col(1) - Vector3d(0, 1, 0)).norm(), 0, 1e-12);
    const Frame frame = hit.frame();
    EXPECT_NEAR((frame.uAxis - Vector3d(1, 0, 2).normalized()).norm(), 0, 1e-12);
    EXPECT_NEAR(frame.uAxis.cross(frame.vAxis).dot(frame.normal), 1.0, 1e-12);
  }
}

TEST(DomainLocator, OutsideExtrapolatesFromTheNearestTriangle) {
  const Parameterization param = tiltedPlane();
  const DomainLocator locator(param);
  const DomainHit hit = locator.locate({5, 2});
  EXPECT_FALSE(hit.inside);
  // The plane's affine map continues linearly beyond the canvas.
  EXPECT_NEAR((hit.point - Vector3d(5, 2, 11)).norm(), 0, 1e-12);
}

// A fold whose triangles reach past the canvas' outline (an interior vertex pulled beyond the top
// edge, as a handle's arch can lie over and beyond its base) is nearer to points above it than
// the outline is; outside the canvas the map still continues the outline's own sheet, so that
// neighbouring points do not jump between sheets.
TEST(DomainLocator, OutsideContinuesTheOutlineNotAFoldReachingPastIt) {
  Parameterization param = tiltedPlane();
  param.uv[2 * 5 + 2] = {2.0, 4.6};  // vertex (2, 2) folded over the top edge y = 4
  const DomainLocator locator(param);
  for (const Vector2d& u : {Vector2d(2.0, 4.8), Vector2d(1.7, 4.9), Vector2d(2.3, 5.2)}) {
    const DomainHit hit = locator.locate(u);
    EXPECT_FALSE(hit.inside);
    // A face on the top edge, whose affine map is the plane's.
    EXPECT_NEAR((hit.point - Vector3d(u.x(), u.y(), 2 * u.x() + 1)).norm(), 0, 1e-12)
        << u.transpose();
    int onOutline = 0;
    for (auto v : param.canvas->surface.fv_range(TriMesh::FaceHandle(hit.face)))
      onOutline += param.uv[std::size_t(v.idx())].y() == 4.0;
    EXPECT_EQ(onOutline, 2) << u.transpose();
  }
}

TEST(DomainLocator, PrefersFacesThatAreNotReversed) {
  Parameterization param = tiltedPlane();
  // Fold: move the uv of vertex (1,1) over (2,2), so faces overlap in uv.
  param.uv[6] = {2.5, 2.5};
  param.reversedFaces.assign(param.canvas->surface.n_faces(), 0);
  const DomainLocator plain(param);
  const int first = plain.locate({2.2, 2.4}).face;
  param.reversedFaces[first] = 1;
  const DomainLocator locator(param);
  const DomainHit hit = locator.locate({2.2, 2.4});
  EXPECT_TRUE(hit.inside);
  EXPECT_NE(hit.face, first);
  EXPECT_EQ(param.reversedFaces[hit.face], 0);
}
