// A plugin whose registration throws.
#include <stdexcept>

#include "geobrush/registry.hpp"

static void registerNodes(geobrush::PluginRegistrar&) {
  throw std::runtime_error("registration exploded");
}

GEOBRUSH_PLUGIN(registerNodes)
