// Every shipped graph writes meshes without self-intersecting faces, by CGAL's exact test: the
// meshes they read have none, so any would be new.
#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include "cgal_reference.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

class ShippedGraph : public testing::TestWithParam<std::string> {};

TEST_P(ShippedGraph, WritesMeshesWithoutSelfIntersections) {
  const auto dir = test::tempDir("reference-" + GetParam());
  const EvalReport report = test::runGraphFile(test::sourceDir() / "graphs" / GetParam(), dir);
  ASSERT_TRUE(report.ok) << report.error;
  for (const auto& path : report.filesWritten) {
    if (path.extension() != ".obj") continue;
    EXPECT_EQ(test::cgalSelfIntersections(readMesh(path).mesh->surface), 0u) << path;
  }
}

INSTANTIATE_TEST_SUITE_P(Graphs, ShippedGraph, testing::ValuesIn(test::shippedGraphs()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(0, info.param.size() - 5);
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace geobrush
