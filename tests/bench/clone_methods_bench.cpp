// The live brush through each clone method's graph (graphs/methods), on one scene and with one
// dab sequence, in one process: what a dab costs with each pipeline.
#include <benchmark/benchmark.h>

#include <array>
#include <string>
#include <vector>

#include "graph_edits.hpp"

namespace geobrush {
namespace {

constexpr std::array<const char*, 2> kMethods = {"geobrush", "dpm"};

// BM_LiveBrushGraph's scene (pipeline_bench): a 280^2 relief plane as the source with a canvas of
// radius 0.9, a geodesic sphere of `sphereResolution` as the target at (0, 0, 1), scale 0.3.
Graph liveBrushScene(const std::string& method, int sphereResolution) {
  Graph graph = bench::proceduralClone(method, sphereResolution, 0.12, 0.3);
  graph.nodes.at("source_canvas").params["dabs"] = std::vector<double>{0, 0, 0, 0.9};
  return graph;
}

// Argument 0: the method (0 geobrush, 1 dpm); argument 1: the sphere's resolution (128: 164k
// vertices). A first stroke of one dab evaluated untimed, then one dab of radius 0.12 appended per
// iteration, moving along a line as BM_LiveBrushGraph's do, and the paste evaluated. Counters:
// the median, 90th percentile and largest dab, and each node's mean time per dab.
void BM_LiveBrushMethod(benchmark::State& state) {
  const std::string method = kMethods.at(std::size_t(state.range(0)));
  Graph graph = liveBrushScene(method, int(state.range(1)));
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.targets = {"stitch"};
  std::vector<double> dabs = {-0.3, -0.1, 0.12, 1};
  graph.nodes.at("strokes").params["dabs"] = dabs;
  bench::EditTimer timer;
  if (!timer.evaluate(state, evaluator, graph, options, true)) return;
  int dab = 0;
  for (auto _ : state) {
    ++dab;
    dabs.insert(dabs.end(), {-0.3 + 0.02 * dab, -0.1 + 0.007 * dab, 0.12, 1});
    graph.nodes.at("strokes").params["dabs"] = dabs;
    if (!timer.evaluate(state, evaluator, graph, options)) return;
  }
  timer.report(state, "dab");
  state.SetLabel(method);
}

}  // namespace
}  // namespace geobrush

BENCHMARK(geobrush::BM_LiveBrushMethod)
    ->ArgsProduct({{0, 1}, {128}})
    ->Iterations(30)
    ->Unit(benchmark::kMillisecond);
