// The preprocess value types: content hashes follow every field.
#include <gtest/gtest.h>

#include "direct_context.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/derived_store.hpp"
#include "mesh_checks.hpp"

using namespace geobrush;

namespace {

Canvas unitCanvas() {
  Canvas canvas;
  canvas.surface = test::tetrahedron({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}).surface;
  canvas.sourceVertex = {0, 1, 2, 3};
  canvas.sourceFace = {0, 1, 2, 3};
  canvas.originFace = 0;
  canvas.originVertex = 0;
  return canvas;
}

}  // namespace

TEST(CanvasValues, HashesFollowEveryField) {
  const Canvas base = unitCanvas();
  EXPECT_EQ(base.contentHash(), unitCanvas().contentHash());
  Canvas moved = base;
  moved.surface.point(TriMesh::VertexHandle(2))[1] += 1e-12;
  EXPECT_NE(moved.contentHash(), base.contentHash());
  Canvas origin = base;
  origin.originVertex = 1;
  EXPECT_NE(origin.contentHash(), base.contentHash());

  auto canvas = std::make_shared<const Canvas>(base);
  Parameterization a;
  a.canvas = canvas;
  a.uv = {{0, 0}, {1, 0}, {0, 1}, {0.3, 0.3}};
  Parameterization b = a;
  b.uv[3].x() = 0.31;
  EXPECT_NE(a.contentHash(), b.contentHash());
  b = a;
  b.reversedFaces = {0, 0, 1, 0};
  EXPECT_NE(a.contentHash(), b.contentHash());
  b = a;
  b.origin.vAxis = -b.origin.vAxis;
  EXPECT_NE(a.contentHash(), b.contentHash());

  auto cage = std::make_shared<Cage>();
  cage->mesh = base.surface;
  cage->top = {0};
  cage->bottom = {1};
  Cage other = *cage;
  other.bottom = {2};
  EXPECT_NE(cage->contentHash(), other.contentHash());

  GreenCoordinates gc;
  gc.cage = cage;
  gc.phi = Eigen::MatrixXd::Constant(2, 4, 0.25);
  gc.psi = Eigen::MatrixXd::Zero(2, 4);
  GreenCoordinates gc2 = gc;
  gc2.psi(1, 3) = 1e-15;
  EXPECT_NE(gc.contentHash(), gc2.contentHash());
  EXPECT_EQ(gc.summary(), "Green coordinates of 2 points");
}

TEST(CanvasValues, TheZeroDraftIsDerivedOncePerSourceWhereNoDraftIsConnected) {
  const NodeType paste = NodeTypeBuilder("test.paste", 1)
                             .input<Parameterization>("source", "E_s.")
                             .optionalInput<Mesh>("draft", "G.")
                             .compute([](Context&) {})
                             .build();
  auto source = std::make_shared<Parameterization>();
  auto canvas = std::make_shared<Canvas>();
  canvas->surface = test::icosphere(1);
  source->canvas = canvas;
  auto store = std::make_shared<DerivedStore>();
  test::DirectContext first(paste, {{"source", source}}, {}, store);
  const MeshPtr zero = draftOrZero(first);
  ASSERT_EQ(zero->surface.n_vertices(), canvas->surface.n_vertices());
  for (auto v : zero->surface.vertices())
    EXPECT_EQ(zero->surface.point(v), TriMesh::Point(0, 0, 0));
  test::DirectContext again(paste, {{"source", source}}, {}, store);
  EXPECT_EQ(draftOrZero(again), zero);
  EXPECT_EQ(store->builds(), 1u);

  auto draft = std::make_shared<const Mesh>(canvas->surface);
  test::DirectContext drafted(paste, {{"source", source}, {"draft", draft}}, {}, store);
  EXPECT_EQ(draftOrZero(drafted), draft);

  auto moved = std::make_shared<Parameterization>(*source);
  auto otherCanvas = std::make_shared<Canvas>(*canvas);
  otherCanvas->surface = test::icosphere(2);
  moved->canvas = otherCanvas;
  test::DirectContext other(paste, {{"source", moved}}, {}, store);
  EXPECT_EQ(draftOrZero(other)->surface.n_vertices(), otherCanvas->surface.n_vertices());
  EXPECT_EQ(store->builds(), 2u);
}
