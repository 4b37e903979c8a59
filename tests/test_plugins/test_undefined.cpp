// A plugin that needs a symbol nobody defines: loading must fail cleanly.
#include "geobrush/registry.hpp"

extern "C" int geobrush_symbol_that_does_not_exist();

static void registerNodes(geobrush::PluginRegistrar&) {
  geobrush_symbol_that_does_not_exist();
}

GEOBRUSH_PLUGIN(registerNodes)
