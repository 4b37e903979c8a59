// Evaluator overhead: a chain of N cheap nodes evaluated cold (every node
// computes), warm (every node is a cache hit), and after one change at the
// far end of the chain (one node recomputes). The nodes do almost nothing,
// so these numbers are the framework's own cost per node.
#include <benchmark/benchmark.h>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

// n0 -> add1 -> add2 -> ... -> add{N-1}, plus an unrelated number "z".
Graph chain(int length) {
  Graph graph;
  graph.nodes["n0"] = {"test.number", 1, {}};
  graph.nodes["z"] = {"test.number", 1, {}};
  std::string previous = "n0";
  for (int i = 1; i < length; ++i) {
    const std::string name = "add" + std::to_string(i);
    graph.nodes[name] = {"test.add", 2, {}};
    graph.connections.push_back({{previous, "value"}, {name, "a"}});
    previous = name;
  }
  prepareGraph(graph, test::testNodeRegistry());
  return graph;
}

void BM_EvaluateCold(benchmark::State& state) {
  const Graph graph = chain(int(state.range(0)));
  for (auto _ : state) {
    Evaluator evaluator(test::testNodeRegistry());
    benchmark::DoNotOptimize(evaluator.evaluate(graph).ok);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_EvaluateAllCacheHits(benchmark::State& state) {
  const Graph graph = chain(int(state.range(0)));
  Evaluator evaluator(test::testNodeRegistry());
  evaluator.evaluate(graph);
  for (auto _ : state)
    benchmark::DoNotOptimize(evaluator.evaluate(graph).ok);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_EvaluateUnrelatedChange(benchmark::State& state) {
  Graph graph = chain(int(state.range(0)));
  Evaluator evaluator(test::testNodeRegistry());
  evaluator.evaluate(graph);
  double value = 0;
  for (auto _ : state) {
    graph.nodes["z"].params["value"] = value++;
    benchmark::DoNotOptimize(evaluator.evaluate(graph).ok);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

}  // namespace

BENCHMARK(BM_EvaluateCold)->Arg(10)->Arg(100)->Arg(1000);
BENCHMARK(BM_EvaluateAllCacheHits)->Arg(10)->Arg(100)->Arg(1000);
BENCHMARK(BM_EvaluateUnrelatedChange)->Arg(10)->Arg(100)->Arg(1000);
