#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "geobrush/cut_paste.hpp"

namespace geobrush {
namespace {

std::vector<char> interior(const TriMesh& mesh) {
  std::vector<char> movable(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices())
    movable[std::size_t(v.idx())] = !mesh.is_boundary(v);
  return movable;
}

TEST(CutPaste, SmoothingToRestIsTheLimitOfTheUmbrellaPasses) {
  const MeshPtr bumpy = test::heightGrid(8, [](double x, double y) { return std::sin(3 * x * y); });
  TriMesh passes = bumpy->surface, rest = bumpy->surface;
  umbrellaSmooth(passes, interior(passes), 3000);
  umbrellaSmoothToRest(rest, interior(rest));
  for (auto v : rest.vertices()) {
    EXPECT_LT((pointOf(rest, v.idx()) - pointOf(passes, v.idx())).norm(), 1e-9);
    if (rest.is_boundary(v)) {
      EXPECT_EQ(rest.point(v), bumpy->surface.point(v));  // the boundary stays
    }
  }
}

TEST(CutPaste, APlanarGridAtRestStaysInItsPlane) {
  Eigen::Isometry3d tilt = Eigen::Isometry3d::Identity();
  tilt.rotate(Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 0).normalized()));
  const MeshPtr plane = test::heightGrid(
      6, [](double, double) { return 0.0; }, tilt);
  TriMesh rest = plane->surface;
  umbrellaSmoothToRest(rest, interior(rest));
  const Eigen::Vector3d normal = tilt.linear() * Eigen::Vector3d::UnitZ();
  for (auto v : rest.vertices())
    EXPECT_NEAR(pointOf(rest, v.idx()).dot(normal), 0.0, 1e-12);
}

// On a plane parameterized by its own coordinates, the frame field is the plane's axes, and an
// offset encoded in either frame decodes back to the point, also over a moved (rotated, scaled)
// copy of the base, where it turns and scales with it.
TEST(CutPaste, FramesOfAPlaneAreItsAxesAndOffsetsMoveWithTheBase) {
  const MeshPtr plane = test::heightGrid(4, [](double, double) { return 0.0; });
  std::vector<Eigen::Vector2d> uv;
  for (auto v : plane->surface.vertices())
    uv.emplace_back(plane->surface.point(v)[0], plane->surface.point(v)[1]);
  const BaseFrameField field = baseFrameField(plane->surface, uv);
  for (std::size_t v = 0; v < uv.size(); ++v) {
    EXPECT_LT((field.normal[v] - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    EXPECT_LT((field.tangent[v] - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  }
  TriMesh moved = plane->surface;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1, 2).normalized()).toRotationMatrix();
  for (auto v : moved.vertices()) {
    const Eigen::Vector3d p = 2.5 * (turn * pointOf(moved, v.idx()));
    moved.set_point(v, toPoint(p));
  }
  const BaseFrameField movedField = baseFrameField(moved, uv);
  const Eigen::Vector3d b(0.2, 0.5, 0.3), x(0.1, -0.05, 0.4);
  for (DetailMethod method : {DetailMethod::FaceFrame, DetailMethod::SmoothFrame}) {
    const BaseFace face = baseFace(plane->surface, field, 7);
    const Eigen::Vector3d offset = encodeOffset(face, b, x, method);
    const Eigen::Vector3d back = decodeOffset(face, b, offset, method, 1.0);
    EXPECT_LT((back - x).norm(), 1e-12);
    const Eigen::Vector3d there =
        decodeOffset(baseFace(moved, movedField, 7), b, offset, method, 2.5);
    EXPECT_LT((there - 2.5 * (turn * x)).norm(), 1e-12) << int(method);
  }
}

TEST(CutPaste, TheSimilarityFitRecoversATurnScaleAndShift) {
  const Eigen::Rotation2Dd turn(0.8);
  std::vector<Eigen::Vector2d> from, to;
  for (int k = 0; k < 7; ++k) {
    from.emplace_back(std::cos(k * 1.3) * (1 + 0.1 * k), std::sin(k * 0.7));
    to.push_back(1.7 * (turn * from.back()) + Eigen::Vector2d(3, -2));
  }
  const Eigen::Matrix3d s = fitSimilarity2d(from, to);
  for (std::size_t k = 0; k < from.size(); ++k)
    EXPECT_LT(((s * from[k].homogeneous()).hnormalized() - to[k]).norm(), 1e-12);
  // A mirrored copy is no similarity: the fit stays a rotation.
  std::vector<Eigen::Vector2d> mirrored;
  for (const auto& p : to)
    mirrored.emplace_back(p.x(), -p.y());
  const Eigen::Matrix3d fit = fitSimilarity2d(from, mirrored);
  const double determinant = fit.topLeftCorner<2, 2>().determinant();
  EXPECT_GT(determinant, 0);
}

}  // namespace
}  // namespace geobrush
