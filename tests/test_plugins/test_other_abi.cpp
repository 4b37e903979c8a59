// A plugin built against another plugin ABI.
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

using namespace geobrush;

extern "C" __attribute__((visibility("default"))) int geobrush_plugin_abi_version() {
  return 999;  // no GeoBrush has had this ABI
}
extern "C" __attribute__((visibility("default"))) void geobrush_plugin_register(
    PluginRegistrar& r) {
  r.add(NodeTypeBuilder("test.other_abi", 1)
            .doc("Never registered.")
            .output<Scalar>("value", "Nothing.")
            .compute([](Context&) {})
            .build());
}
