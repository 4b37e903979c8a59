// Handle edits as the studio runs them. BM_HandleDrag: a 450k-vertex template (the paper's
// largest model), a plane primitive of 671^2 vertices, edited by two rows; the last row's handle
// is dragged (only its translation changes) and the graph re-evaluated through one evaluator, so
// the kNN graph, D(x, L) and the regions come from derived data. BM_NefertitiDrag: the same drag
// of a point handle on the 35k-vertex nefertiti with its back hole. BM_HandleEditCold: the plane
// graph in a fresh evaluator (the template's own time in the template_ms counter).
#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/memory.hpp"
#include "geobrush/mesh.hpp"
#include "graph_edits.hpp"
#include "test_support.hpp"

namespace {

using geobrush::Graph;
using geobrush::GraphNode;
using Rows = std::function<std::vector<double>(double dx, double dz)>;

static const bool kReusesFreedMemory = geobrush::reuseFreedMemory();

constexpr std::int64_t kResolution = 670;  // 671^2 = 450241 vertices

GraphNode plane() {
  return {"geobrush.primitive",
          1,
          {{"shape", std::string("plane")}, {"size", 2.0}, {"resolution", kResolution}}};
}

// The first row raises a region and turns it; the second, the dragged one, moves a small region.
std::vector<double> planeRows(double dx, double dz) {
  return {-0.3, 0.2, 0, 0.1, 0, 0, 0.2, 0, 0, 1, 15, 0.3, 0, 0, 0.02, dx, 0, dz, 0, 0, 1, 0};
}

Graph templateGraph(const GraphNode& source, const std::vector<double>& rows) {
  Graph graph;
  graph.nodes["template"] = source;
  graph.nodes["handle_edit"] = {"geobrush.handle_edit", 1, {{"edits", rows}}};
  graph.connections.push_back({{"template", "mesh"}, {"handle_edit", "template"}});
  geobrush::prepareGraph(graph, geobrush::test::registry());
  return graph;
}

// Drags the last row's translation (dx, 0, dz) around a circle of radius scale / 2 about
// (0, 0, scale), one evaluation per step; the first evaluation is not timed.
void drag(benchmark::State& state, const GraphNode& source, const Rows& rows, double scale) {
  geobrush::Evaluator evaluator(geobrush::test::registry());
  geobrush::bench::EditTimer timer;
  if (!timer.evaluate(state, evaluator, templateGraph(source, rows(0, scale)), {}, true)) return;
  int step = 0;
  for (auto _ : state) {
    const double phase = 0.1 * ++step;
    state.PauseTiming();
    const Graph dragged = templateGraph(
        source, rows(0.5 * scale * std::sin(phase), scale * (1 + 0.5 * std::cos(phase))));
    state.ResumeTiming();
    if (!timer.evaluate(state, evaluator, dragged, {})) return;
  }
  timer.report(state, "drag");
  if (const auto mesh =
          std::dynamic_pointer_cast<const geobrush::Mesh>(evaluator.output("template", "mesh")))
    state.counters["vertices"] = double(mesh->surface.n_vertices());
}

void BM_HandleDrag(benchmark::State& state) {
  drag(state, plane(), planeRows, 0.1);
}
BENCHMARK(BM_HandleDrag)->Unit(benchmark::kMillisecond)->Iterations(30);

void BM_NefertitiDrag(benchmark::State& state) {
  const GraphNode head = {
      "geobrush.load_mesh",
      1,
      {{"path", geobrush::test::meshPath("cases/nefertiti_back_hole.obj").string()}}};
  // A handle of radius 5 on the front (+z), far from the hole at the back.
  const Rows rows = [](double dx, double dz) {
    return std::vector<double>{0, 0, 181, 5, dx, 0, dz, 0, 0, 1, 0};
  };
  drag(state, head, rows, 10);
}
BENCHMARK(BM_NefertitiDrag)->Unit(benchmark::kMillisecond)->Iterations(30);

void BM_HandleEditCold(benchmark::State& state) {
  geobrush::bench::EditTimer timer;
  const Graph graph = templateGraph(plane(), planeRows(0, 0.1));
  for (auto _ : state) {
    geobrush::Evaluator evaluator(geobrush::test::registry());
    if (!timer.evaluate(state, evaluator, graph, {})) return;
  }
  timer.report(state, "cold");
}
BENCHMARK(BM_HandleEditCold)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
