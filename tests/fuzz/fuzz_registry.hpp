// The node types the graph targets check against: every plugin of the build.
#pragma once

#include "geobrush/registry.hpp"

namespace geobrush::fuzz {

// Loaded once per process from the build's plugin folder (GEOBRUSH_FUZZ_PLUGIN_DIR).
const NodeRegistry& registry();

}  // namespace geobrush::fuzz
