#include "signal_fidelity.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "emd_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"
#include "laplacian_system.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

MeshPtr sphereOfRadius(double radius) {
  TriMesh sphere = test::icosphere(4);
  for (auto v : sphere.vertices())
    sphere.set_point(v, sphere.point(v) * radius);
  return std::make_shared<const Mesh>(sphere);
}

// The cap of `mesh` above height z.
std::vector<int> capAbove(const TriMesh& mesh, double z) {
  std::vector<int> vertices;
  for (auto v : mesh.vertices())
    if (mesh.point(v)[2] > z) vertices.push_back(v.idx());
  return vertices;
}

// A surface measured against its own signal scaled by c misses it by |1 - c| / |c|, on the
// region's interior alone: what lies off it, or on its border, does not count.
TEST(SignalFidelity, IsTheRelativeErrorOfTheSignalOverTheInterior) {
  const MeshPtr bump =
      test::heightGrid(12, [](double x, double y) { return 0.3 * std::exp(-4 * (x * x + y * y)); });
  const LaplacianSystem system = buildLaplacianSystem(bump, capAbove(bump->surface, 0.05), {});
  ASSERT_FALSE(system.boundary.empty());
  const std::vector<double> g = test::wholeMeshSignal(bump->surface);
  EXPECT_LT(signalFidelity(system, bump->surface, g, {}), 1e-12);
  for (double c : {2.0, 0.5, -1.0}) {
    std::vector<double> scaled = g;
    for (double& value : scaled)
      value *= c;
    EXPECT_NEAR(signalFidelity(system, bump->surface, scaled, {}), std::abs(1 - c) / std::abs(c),
                1e-12)
        << c;
  }
  // Values off the interior are not read.
  std::vector<double> changed = g;
  std::vector<std::uint8_t> interior(g.size(), 0);
  for (std::size_t i = 0; i < system.vertices.size(); ++i)
    interior[std::size_t(system.vertices[i])] = 1;
  for (int i : system.boundary)
    interior[std::size_t(system.vertices[std::size_t(i)])] = 0;
  for (std::size_t v = 0; v < changed.size(); ++v)
    if (!interior[v]) changed[v] = 1e3;
  EXPECT_LT(signalFidelity(system, bump->surface, changed, {}), 1e-12);
  EXPECT_THROW(signalFidelity(system, bump->surface, std::vector<double>(3, 0.0), {}),
               std::invalid_argument);
}

// On a sphere of radius R the signal per unit area is -4 / R (EMD spec T1): a cap of a fine
// sphere carries it to within the discretization's error, and raw values are off by the areas.
TEST(SignalFidelity, FindsTheSpheresCurvatureInACap) {
  const double radius = 2.0;
  const MeshPtr sphere = sphereOfRadius(radius);
  const LaplacianSystem system =
      buildLaplacianSystem(sphere, capAbove(sphere->surface, 0.5 * radius), {});
  const std::vector<double> density(sphere->surface.n_vertices(), -4 / radius);
  EXPECT_LT(signalFidelity(system, sphere->surface, density, {.perArea = true}), 0.02);
  EXPECT_GT(signalFidelity(system, sphere->surface, density, {}), 0.9);
}

// The node on a real mesh rebuilt from its own signal: the rebuilt surface carries it.
TEST(SignalFidelityNode, MeasuresARegionOfARealMeshRebuiltFromItsOwnSignal) {
  const auto [bunny, param, signal, system] = test::bunnyRegion();
  ASSERT_TRUE(signal && system);
  const auto rebuilt =
      test::runNode("geobrush.laplacian_reconstruct", {{"system", system}, {"signal", signal}},
                    {{"field", std::string("g")}})
          .get<Mesh>("mesh");
  ASSERT_TRUE(rebuilt);
  const auto report = test::runNode("geobrush.signal_fidelity",
                                    {{"system", system}, {"mesh", rebuilt}, {"signal", signal}},
                                    {{"field", std::string("g")}})
                          .get<Metrics>("report");
  ASSERT_TRUE(report);
  EXPECT_LT(report->values.at("signal_fidelity"), 1e-9);

  using Inputs = std::map<std::string, ValuePtr, std::less<>>;
  const auto failsAt = [&](const Inputs& inputs, const ParamMap& params) {
    try {
      test::runNode("geobrush.signal_fidelity", inputs, params);
    } catch (const NodeError& e) {
      return e.where();
    }
    return std::string("no error");
  };
  const MeshPtr plane = test::heightGrid(3, [](double, double) { return 0.0; });
  auto other = std::make_shared<VertexFields>(plane->surface);
  EXPECT_EQ(failsAt({{"system", system}, {"mesh", rebuilt}, {"signal", other}}, {}),
            "input 'signal'");
  EXPECT_EQ(failsAt({{"system", system}, {"mesh", plane}, {"signal", signal}},
                    {{"field", std::string("g")}}),
            "input 'mesh'");
  EXPECT_EQ(failsAt({{"system", system}, {"mesh", rebuilt}, {"signal", signal}}, {}),
            "param 'field'");
}

}  // namespace
}  // namespace geobrush
