#include "test_support.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

namespace geobrush::test {

std::filesystem::path meshDir() {
  return std::filesystem::weakly_canonical(GEOBRUSH_MESH_DIR);
}
std::filesystem::path meshPath(const std::string& name) { return meshDir() / name; }
std::filesystem::path sourceDir() { return GEOBRUSH_SOURCE_DIR; }
std::filesystem::path pluginDir() { return GEOBRUSH_PLUGIN_DIR; }
std::filesystem::path testPluginDir() { return GEOBRUSH_TEST_PLUGIN_DIR; }
std::filesystem::path cliPath() { return GEOBRUSH_CLI; }

const NodeRegistry& registry() {
  static NodeRegistry* instance = [] {
    auto* r = new NodeRegistry();
    auto report = r->loadPlugins({pluginDir()});
    for (const auto& error : report.errors) ADD_FAILURE() << error;
    return r;
  }();
  return *instance;
}

std::filesystem::path tempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("geobrush-test-" + std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  struct Cleanup {
    std::filesystem::path root;
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(root, ec);
    }
  };
  static std::vector<std::unique_ptr<Cleanup>> cleanups;
  cleanups.push_back(std::make_unique<Cleanup>(Cleanup{dir}));
  return dir;
}

}  // namespace geobrush::test
