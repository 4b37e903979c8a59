// Built twice (test_dup_a, test_dup_b): the second library declares a type
// id that the first already provides.
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"

using namespace geobrush;

static void registerNodes(PluginRegistrar& r) {
  r.add(NodeTypeBuilder("test.duplicate", 1)
            .doc("Provided by two libraries.")
            .output<Scalar>("value", "A number.")
            .compute([](Context& ctx) { ctx.out("value", std::make_shared<Scalar>(1.0)); })
            .build());
}

GEOBRUSH_PLUGIN(registerNodes)
