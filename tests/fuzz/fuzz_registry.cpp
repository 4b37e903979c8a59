#include "fuzz_registry.hpp"

#include <cstdio>
#include <cstdlib>

namespace geobrush::fuzz {

const NodeRegistry& registry() {
  static const NodeRegistry* instance = [] {
    auto* loaded = new NodeRegistry();
    const auto report = loaded->loadPlugins({GEOBRUSH_FUZZ_PLUGIN_DIR});
    if (!report.errors.empty() || loaded->types().empty()) {
      std::fprintf(stderr, "fuzz: the build's plugins did not load from %s\n",
                   GEOBRUSH_FUZZ_PLUGIN_DIR);
      std::abort();
    }
    return loaded;
  }();
  return *instance;
}

}  // namespace geobrush::fuzz
