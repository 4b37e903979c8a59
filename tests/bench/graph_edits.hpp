// Timing a graph's re-evaluations after edits through one evaluator, as an artist's drags and
// dabs re-evaluate it: each edit's wall time and the nodes' own times, as benchmark counters.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"

namespace geobrush::bench {

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
