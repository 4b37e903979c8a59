// EMD detail transfer at interactive rates: the decomposition of a large mesh (offline, cached),
// and through the emd method's graph the two edits an artist makes: moving a gain of the
// equalizer (the factored system re-used: transfer, back-substitution, belt) and painting a dab
// (the region's system refactored).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>

#include "emd.hpp"
#include "geobrush/clone.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/laplacian.hpp"
#include "geobrush/registry.hpp"
#include "graph_edits.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

MeshPtr primitive(const ParamMap& params) {
  Graph graph;
  graph.nodes["mesh"] = GraphNode{"geobrush.primitive", 1, params};
  Evaluator evaluator(test::registry());
  if (!evaluator.evaluate(graph).ok) return nullptr;
  return std::dynamic_pointer_cast<const Mesh>(evaluator.output("mesh", "mesh"));
}

// Argument 0: the relief plane's quads per side ((r + 1)^2 vertices); argument 1: the envelope
// (0 biharmonic, 1 harmonic). One whole-mesh decomposition of Eq. 1's signal per iteration, three
// modes.
void BM_EmdDecomposition(benchmark::State& state) {
  const MeshPtr plane = primitive({{"shape", std::string("plane")},
                                   {"size", 2.0},
                                   {"resolution", std::int64_t(state.range(0))},
                                   {"relief", 0.02}});
  const TriMesh& mesh = plane->surface;
  const Eigen::MatrixX3d delta = -(cotangentLaplacian(mesh) * pointMatrix(mesh));
  const auto normals = areaWeightedNormals(mesh);
  std::vector<double> g(mesh.n_vertices());
  for (std::size_t i = 0; i < g.size(); ++i)
    g[i] = delta.row(Eigen::Index(i)).dot(normals[i]);
  int sifts = 0;
  for (auto _ : state) {
    const EmdResult result = empiricalModeDecomposition(
        mesh, g, {.envelope = state.range(1) == 0 ? Envelope::biharmonic : Envelope::harmonic});
    sifts = 0;
    for (const auto& mode : result.reports)
      sifts += mode.sifts;
  }
  state.counters["vertices"] = double(mesh.n_vertices());
  state.counters["sifts"] = sifts;
}

// The emd method with a relief plane as the source and a geodesic sphere of resolution 150
// (225,002 vertices) as the target, the painted region about 20k of its vertices.
Graph emdGraph() {
  return bench::proceduralClone("emd", 150, 0.4, 1.5);
}

// Argument 0: the edit (0: a gain of the equalizer moved, 1: a dab painted, moving along the
// region's edge); argument 1: the system's form (0 screened, 1 Eq. 8's least squares). Counters:
// the median and 90th percentile edit, the nodes' mean times, the region's target vertices.
void BM_EmdEdit(benchmark::State& state) {
  Graph graph = emdGraph();
  graph.nodes.at("system").params["form"] =
      std::string(state.range(1) == 0 ? "screened" : "least_squares");
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.targets = {"belt"};
  bench::EditTimer timer;
  if (!timer.evaluate(state, evaluator, graph, options, true)) return;
  int step = 0;
  for (auto _ : state) {
    ++step;
    if (state.range(0) == 0) {
      graph.nodes.at("transfer").params["gains"] =
          std::vector<double>{1.0 + 0.1 * (step % 7), 1.0, 1.0 - 0.05 * (step % 5)};
    } else {
      const double angle = 0.3 * step;
      graph.nodes.at("strokes").params["dabs"] =
          std::vector<double>{0, 0, 0.4, 1, 0.4 * std::cos(angle), 0.4 * std::sin(angle), 0.05, 1};
    }
    if (!timer.evaluate(state, evaluator, graph, options)) return;
  }
  timer.report(state, "edit");
  const auto system =
      std::dynamic_pointer_cast<const LaplacianSystem>(evaluator.output("system", "system"));
  state.counters["region_vertices"] = system ? double(system->vertices.size()) : 0.0;
  state.counters["target_vertices"] = double(system ? system->mesh->surface.n_vertices() : 0);
}

}  // namespace
}  // namespace geobrush

BENCHMARK(geobrush::BM_EmdDecomposition)
    ->Args({316, 0})
    ->Args({316, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK(geobrush::BM_EmdEdit)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(20);
