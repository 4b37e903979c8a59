// libFuzzer target: `--set NODE.PARAM=VALUE` on a graph with a node of every loaded type. Every
// input must set a parameter or give a GraphError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_registry.hpp"
#include "geobrush/graph.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const geobrush::Graph kEveryType = [] {
    geobrush::Graph graph;
    graph.file = "fuzz.json";
    for (const geobrush::NodeType* type : geobrush::fuzz::registry().types()) {
      std::string name = type->id.substr(type->id.find('.') + 1);
      graph.nodes[name] = {type->id, type->version, {}};
    }
    return graph;
  }();
  geobrush::Graph graph = kEveryType;
  try {
    geobrush::setParamFromText(graph, geobrush::fuzz::registry(),
                               std::string(reinterpret_cast<const char*>(data), size));
    geobrush::serializeGraph(graph, &geobrush::fuzz::registry());
  } catch (const geobrush::GraphError&) {
  }
  return 0;
}
