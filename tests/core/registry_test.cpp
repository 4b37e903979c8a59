// The plugin loader: valid plugins load, every bad library is refused with a
// message naming it, and the process keeps running.
#include <gtest/gtest.h>

#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

std::string errorFor(const NodeRegistry::LoadReport& report, const std::string& file) {
  for (const auto& error : report.errors)
    if (error.find("/" + file + ":") != std::string::npos) return error;
  return "";
}

}  // namespace

TEST(Registry, LoadsGoodPluginsAndRefusesBadOnes) {
  NodeRegistry registry;
  auto report = registry.loadPlugins({test::testPluginDir()});
  EXPECT_NE(registry.find("test.number"), nullptr);
  EXPECT_NE(registry.find("test.duplicate"), nullptr);
  EXPECT_EQ(registry.find("test.other_abi"), nullptr);
  EXPECT_EQ(report.loaded.size(), 2u);  // test_dup_a and test_nodes
  EXPECT_EQ(report.errors.size(), 6u);

  EXPECT_NE(errorFor(report, "test_other_abi.so")
                .find("built for plugin ABI 999, this GeoBrush has ABI " +
                      std::to_string(kPluginAbiVersion)),
            std::string::npos);
  EXPECT_NE(errorFor(report, "test_throws.so").find("plugin refused: registration exploded"),
            std::string::npos);
  EXPECT_NE(
      errorFor(report, "test_dup_b.so").find("node type 'test.duplicate' is already provided by"),
      std::string::npos);
  EXPECT_NE(errorFor(report, "test_not_plugin.so").find("not a GeoBrush plugin"),
            std::string::npos);
  EXPECT_NE(errorFor(report, "test_undefined.so").find("cannot load plugin"), std::string::npos);
  EXPECT_NE(errorFor(report, "test_garbage.so").find("cannot load plugin"), std::string::npos);
  EXPECT_TRUE(registry.refusal("test_other_abi.so").has_value());
}

TEST(Registry, RecordsWhichLibraryProvidesEachType) {
  NodeRegistry registry;
  registry.loadPlugins({test::testPluginDir()});
  EXPECT_NE(registry.find("test.add")->library.find("test_nodes.so"), std::string::npos);
  auto types = registry.types();
  EXPECT_TRUE(
      std::is_sorted(types.begin(), types.end(), [](auto* a, auto* b) { return a->id < b->id; }));
}

TEST(Registry, LoadingTheSameFolderTwiceChangesNothing) {
  NodeRegistry registry;
  registry.loadPlugins({test::testPluginDir()});
  const auto count = registry.types().size();
  auto again = registry.loadPlugins({test::testPluginDir()});
  EXPECT_TRUE(again.loaded.empty());
  EXPECT_EQ(registry.types().size(), count);
}

TEST(Registry, RefusesMalformedDeclarations) {
  NodeRegistry registry;
  auto base = [] {
    return NodeTypeBuilder("acme.node", 1)
        .doc("A node.")
        .output<Scalar>("value", "A value.")
        .compute([](Context&) {});
  };
  EXPECT_NO_THROW(registry.add(base().build()));
  EXPECT_THROW(registry.add(base().build()), RegistryError);  // duplicate id
  EXPECT_THROW(registry.add(NodeTypeBuilder("nodot", 1).doc("x").compute([](Context&) {}).build()),
               RegistryError);
  EXPECT_THROW(registry.add(NodeTypeBuilder("acme.nodoc", 1).compute([](Context&) {}).build()),
               RegistryError);
  auto undocumentedPort = NodeTypeBuilder("acme.port", 1)
                              .doc("x")
                              .output<Scalar>("value", "")
                              .compute([](Context&) {})
                              .build();
  EXPECT_THROW(registry.add(undocumentedPort), RegistryError);
  auto outOfRange = NodeTypeBuilder("acme.range", 1)
                        .doc("x")
                        .paramDouble("r", 5.0, "radius")
                        .range(0, 1)
                        .compute([](Context&) {})
                        .build();
  EXPECT_THROW(registry.add(outOfRange), RegistryError);
  auto badUpgrade = NodeTypeBuilder("acme.upgrade", 1)
                        .doc("x")
                        .compute([](Context&) {})
                        .upgrade(1, [](ParamMap&) {})
                        .build();
  EXPECT_THROW(registry.add(badUpgrade), RegistryError);
}

TEST(Registry, DefaultDirsIncludeThePluginPathVariable) {
  ::setenv("GEOBRUSH_PLUGIN_PATH", "/a/b::/c", 1);
  auto dirs = defaultPluginDirs();
  ::unsetenv("GEOBRUSH_PLUGIN_PATH");
  ASSERT_GE(dirs.size(), 3u);
  EXPECT_EQ(dirs[dirs.size() - 2], "/a/b");
  EXPECT_EQ(dirs.back(), "/c");
  EXPECT_EQ(dirs.front().filename(), "plugins");
  EXPECT_EQ(expectedPluginFile("geobrush.load_mesh"), "geobrush_load_mesh.so");
}
