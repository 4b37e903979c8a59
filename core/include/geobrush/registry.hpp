// Node types known to a host, and the plugins that provide them.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/node.hpp"

namespace geobrush {

// Bumped whenever the node API or a value type changes layout; plugins built
// against another number are refused.
inline constexpr int kPluginAbiVersion = 4;

class RegistryError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

class NodeRegistry {
 public:
  NodeRegistry();
  ~NodeRegistry();
  NodeRegistry(const NodeRegistry&) = delete;
  NodeRegistry& operator=(const NodeRegistry&) = delete;

  // Adds a type; throws RegistryError on a duplicate id or a malformed
  // declaration (missing doc, duplicate port, default outside its range...).
  void add(NodeType type);
  const NodeType* find(std::string_view id) const;
  // Sorted by id.
  std::vector<const NodeType*> types() const;

  // Loads every plugin library in `dirs` (in order, files sorted by name).
  // A library that fails (not loadable, no entry point, other ABI, throws,
  // duplicate type) is refused and reported; the others still load.
  struct LoadReport {
    std::vector<std::filesystem::path> loaded;
    std::vector<std::string> errors;  // one line each, naming the library
  };
  LoadReport loadPlugins(const std::vector<std::filesystem::path>& dirs);
  // Loads one library; throws RegistryError naming it.
  void loadPlugin(const std::filesystem::path& library);
  const std::vector<std::filesystem::path>& searchedDirs() const { return searchedDirs_; }
  // Why the library with this file name (e.g. "geobrush_gdem.so") was
  // refused, if it was.
  std::optional<std::string> refusal(const std::string& fileName) const;

 private:
  struct Loaded;
  std::vector<std::unique_ptr<NodeType>> types_;
  std::vector<std::unique_ptr<Loaded>> libraries_;
  std::vector<std::filesystem::path> searchedDirs_;
  std::map<std::string, std::string> refusals_;  // by file name
};

// The folder of the GeoBrush core library (<build>/lib, or <prefix>/<libdir> when installed):
// plugins and shared data are found relative to it, whichever program loaded it (geobrush, the
// studio, a Python interpreter). Empty if it cannot be told.
std::filesystem::path coreLibraryDir();

// The plugin directory of this build or installation (<core library dir>/geobrush/plugins),
// then each entry of GEOBRUSH_PLUGIN_PATH (colon-separated).
std::vector<std::filesystem::path> defaultPluginDirs();

// The name of the library expected to provide a type: "geobrush.load_mesh"
// is provided by "geobrush_load_mesh.so".
std::string expectedPluginFile(std::string_view typeId);

// Handed to a plugin's registration function.
class PluginRegistrar {
 public:
  explicit PluginRegistrar(std::vector<NodeType>& sink) : sink_(sink) {}
  void add(NodeType type) { sink_.push_back(std::move(type)); }

 private:
  std::vector<NodeType>& sink_;
};

}  // namespace geobrush

// Every plugin library defines its entry points with this macro, once.
#define GEOBRUSH_PLUGIN(REGISTER_FUNCTION)                                              \
  extern "C" __attribute__((visibility("default"))) int geobrush_plugin_abi_version() { \
    return ::geobrush::kPluginAbiVersion;                                               \
  }                                                                                     \
  extern "C" __attribute__((visibility("default"))) void geobrush_plugin_register(      \
      ::geobrush::PluginRegistrar& registrar) {                                         \
    REGISTER_FUNCTION(registrar);                                                       \
  }
