// Moving the target point of a clone, topology-free cut and paste beside GeoBrush on the same
// inputs: both method templates (graphs/methods) with a procedural source and target, the
// source side computed once, the target origin moved a step per iteration through the evaluator.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "geobrush/canvas.hpp"
#include "geobrush/clone.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "graph_edits.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// Argument 0: the method (0 geobrush, 1 cutpaste); argument 1: the sphere's resolution. 60 moves
// of 0.004 rad along the sphere; counters: the median, 90th percentile and largest move, the
// nodes' mean times, the feature's and the target's vertices.
void BM_TargetMoveMethod(benchmark::State& state) {
  const std::string method = state.range(0) == 0 ? "geobrush" : "cutpaste";
  const std::string result = state.range(0) == 0 ? "stitch" : "gap";
  Graph graph = bench::proceduralClone(method, int(state.range(1)), 0.285, 0.3);
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.targets = {result};
  auto moveTo = [&](int step) {
    const double angle = 0.004 * step;
    const Eigen::Vector3d origin =
        Eigen::Vector3d(std::sin(angle), 0.3 * std::sin(angle), std::cos(angle)).normalized();
    graph.nodes.at("target_map").params["origin"] = Vec3{origin.x(), origin.y(), origin.z()};
  };
  moveTo(0);
  bench::EditTimer timer;
  if (!timer.evaluate(state, evaluator, graph, options, true)) return;
  int step = 0;
  for (auto _ : state) {
    moveTo(++step);
    if (!timer.evaluate(state, evaluator, graph, options)) return;
  }
  timer.report(state, "move");
  state.counters["target_vertices"] =
      double(std::dynamic_pointer_cast<const Mesh>(evaluator.output("target_mesh", "mesh"))
                 ->surface.n_vertices());
  if (method == "cutpaste")
    state.counters["feature_vertices"] =
        double(std::dynamic_pointer_cast<const Canvas>(evaluator.output("feature", "feature"))
                   ->surface.n_vertices());
}

}  // namespace
}  // namespace geobrush

BENCHMARK(geobrush::BM_TargetMoveMethod)
    ->Args({0, 100})
    ->Args({1, 100})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(60);
