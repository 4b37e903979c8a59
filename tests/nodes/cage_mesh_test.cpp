// geobrush.cage_mesh: a cage's mesh, unchanged.
#include <gtest/gtest.h>

#include "cage_build.hpp"
#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

MeshPtr run(const std::shared_ptr<const Cage>& cage) {
  const NodeType* type = test::registry().find("geobrush.cage_mesh");
  test::DirectContext ctx(*type, {{"cage", cage}});
  type->create()->compute(ctx);
  return std::dynamic_pointer_cast<const Mesh>(ctx.outputs["mesh"]);
}

}  // namespace

TEST(CageMesh, OutputsTheCageSurface) {
  for (auto param : {test::heightFieldParameterization(12, [](double x, double) { return x * x; }),
                     test::terrainParameterization()}) {
    CageBuildOptions options;
    options.resolution = 8;
    auto cage = std::make_shared<const Cage>(buildCage(*param, options).cage);
    const MeshPtr mesh = run(cage);
    ASSERT_TRUE(mesh);
    EXPECT_EQ(mesh->contentHash(), Mesh(cage->mesh).contentHash());
    EXPECT_EQ(meshStats(mesh->surface).boundaryLoops, 0u);
  }
}

TEST(CageMesh, EmptyCageIsAnError) {
  try {
    run(std::make_shared<const Cage>());
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'cage'");
  }
}
