// Benchmarks that edit a clone graph as an artist does: the method templates on procedural
// meshes, and each edit's re-evaluation timed through one evaluator (its wall time and the
// nodes' own times, as benchmark counters).
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "geobrush/clone.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "test_support.hpp"

namespace geobrush::bench {

// A clone method's template (graphs/methods) on procedural meshes: a 280^2 relief plane as the
// source, its canvas of radius 0.45 around the origin, and a geodesic sphere of
// `sphereResolution` (10 r^2 + 2 vertices) as the target at (0, 0, 1); a region of radius
// `strokeRadius` in the domain, pasted at `scale`.
inline Graph proceduralClone(const std::string& method, int sphereResolution, double strokeRadius,
                             double scale) {
  Graph graph = readMethod(method, defaultMethodDirs(), test::registry());
  graph.nodes["source_mesh"] = GraphNode{"geobrush.primitive",
                                         1,
                                         {{"shape", std::string("plane")},
                                          {"size", 2.0},
                                          {"resolution", std::int64_t(280)},
                                          {"relief", 0.02}}};
  graph.nodes["target_mesh"] =
      GraphNode{"geobrush.primitive",
                1,
                {{"shape", std::string("sphere")}, {"resolution", std::int64_t(sphereResolution)}}};
  graph.nodes.at("source_canvas").params = {{"origin", Vec3{0, 0, 0}},
                                            {"dabs", std::vector<double>{0, 0, 0, 0.45}}};
  graph.nodes.at("strokes").params = {{"dabs", std::vector<double>{0, 0, strokeRadius, 1}}};
  graph.nodes.at("target_map").params = {{"origin", Vec3{0, 0, 1}}, {"scale", scale}};
  prepareGraph(graph, test::registry());
  return graph;
}

class EditTimer {
 public:
  // One evaluation, timed unless it is the first (`warmUp`); false, the state skipped with the
  // error, when it fails.
  bool evaluate(benchmark::State& state, Evaluator& evaluator, const Graph& graph,
                const EvalOptions& options, bool warmUp = false) {
    const auto start = std::chrono::steady_clock::now();
    const EvalReport report = evaluator.evaluate(graph, options);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!report.ok) {
      state.SkipWithError(report.error.c_str());
      return false;
    }
    if (warmUp) return true;
    ms_.push_back(ms);
    for (const NodeRun& run : report.runs)
      if (!run.cacheHit) seconds_[run.node] += run.seconds;
    return true;
  }

  // Counters: <node>_ms (each node's mean per edit), <name>_median_ms, <name>_p90_ms and
  // <name>_max_ms over the edits.
  void report(benchmark::State& state, const std::string& name) {
    for (const auto& [node, total] : seconds_)
      state.counters[node + "_ms"] =
          benchmark::Counter(1000 * total, benchmark::Counter::kAvgIterations);
    if (ms_.empty()) return;
    std::vector<double> sorted = ms_;
    std::sort(sorted.begin(), sorted.end());
    state.counters[name + "_median_ms"] = sorted[sorted.size() / 2];
    state.counters[name + "_p90_ms"] = sorted[sorted.size() * 9 / 10];
    state.counters[name + "_max_ms"] = sorted.back();
  }

 private:
  std::map<std::string, double> seconds_;
  std::vector<double> ms_;
};

}  // namespace geobrush::bench
