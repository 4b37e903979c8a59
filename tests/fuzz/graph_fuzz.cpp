// libFuzzer target: the graph-file parser, then the checks against the loaded node types, on
// arbitrary text. Every input must give a graph or a GraphError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_registry.hpp"
#include "geobrush/graph.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    geobrush::Graph graph = geobrush::parseGraph(text, "fuzz.json");
    geobrush::prepareGraph(graph, geobrush::fuzz::registry());
    geobrush::serializeGraph(graph, &geobrush::fuzz::registry());
  } catch (const geobrush::GraphError&) {
  }
  return 0;
}
