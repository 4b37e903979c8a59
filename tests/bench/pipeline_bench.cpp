// The GeoBrush pipeline on a 50k-vertex source canvas (a 224 x 224 height field with relief, the
// whole of it painted): the source preprocess (canvas growth, generalized DEM, cage build and the
// Green-coordinates precompute, each timed on its own and all together; goal <= 0.5 s on 2
// cores), a move of the target canvas over a 163,842-vertex sphere (goal <= 33 ms) and the live
// brush there (one added dab -> stitched mesh; goal <= 16 ms).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include "cage_build.hpp"
#include "cage_fit.hpp"
#include "canvas_grow.hpp"
#include "dem.hpp"
#include "gc_warp.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/exponential_map.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/memory.hpp"
#include "geobrush/stitch.hpp"
#include "membrane.hpp"
#include "membrane_boundary.hpp"
#include "mesh_checks.hpp"
#include "roi.hpp"
#include "test_support.hpp"

using namespace geobrush;

// The pipeline runs as the hosts run it: freed meshes stay in the heap for the next dab.
static const bool kReusesFreedMemory = geobrush::reuseFreedMemory();

namespace {

constexpr int kSide = 223;  // quads per side: 224^2 = 50176 vertices

MeshPtr reliefPatch() {
  TriMesh mesh;
  for (int j = 0; j <= kSide; ++j)
    for (int i = 0; i <= kSide; ++i) {
      const double x = 2.0 * i / kSide - 1, y = 2.0 * j / kSide - 1;
      const double z =
          0.3 * std::exp(-4 * (x * x + y * y)) + 0.02 * std::sin(17 * x) * std::cos(13 * y);
      mesh.add_vertex({x, y, z});
    }
  auto vh = [](int i, int j) { return TriMesh::VertexHandle(j * (kSide + 1) + i); };
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      mesh.add_face(vh(i, j), vh(i + 1, j), vh(i + 1, j + 1));
      mesh.add_face(vh(i, j), vh(i + 1, j + 1), vh(i, j + 1));
    }
  return std::make_shared<const Mesh>(std::move(mesh));
}

struct Stages {
  MeshPtr mesh = reliefPatch();
  CanvasGrowOptions grow;
  Stages() {
    grow.origin = {0, 0, 0.3};
    grow.dabs.push_back({Eigen::Vector3d::Zero(), 10.0});
  }
  std::shared_ptr<Canvas> canvas() const {
    return std::make_shared<Canvas>(growCanvas(mesh, grow));
  }
  std::shared_ptr<Parameterization> map(const std::shared_ptr<Canvas>& canvas) const {
    DemResult dem = discreteExponentialMap(*canvas, DemOptions{});
    auto param = std::make_shared<Parameterization>();
    param->canvas = canvas;
    param->uv = std::move(dem.uv);
    param->normal = std::move(dem.normal);
    param->origin = dem.origin;
    param->reversedFaces = std::move(dem.reversedFaces);
    return param;
  }
};

std::vector<Eigen::Vector3d> points(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> result;
  for (auto v : mesh.vertices())
    result.emplace_back(mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]);
  return result;
}

void BM_CanvasGrow(benchmark::State& state) {
  Stages stages;
  for (auto _ : state)
    benchmark::DoNotOptimize(stages.canvas());
}

void BM_GeneralizedDem(benchmark::State& state) {
  Stages stages;
  auto canvas = stages.canvas();
  for (auto _ : state)
    benchmark::DoNotOptimize(stages.map(canvas));
  state.counters["vertices"] = double(canvas->surface.n_vertices());
}

void BM_CageBuild(benchmark::State& state) {
  Stages stages;
  auto param = stages.map(stages.canvas());
  for (auto _ : state)
    benchmark::DoNotOptimize(buildCage(*param));
}

void BM_GreenCoordinates(benchmark::State& state) {
  Stages stages;
  auto canvas = stages.canvas();
  const Cage cage = buildCage(*stages.map(canvas)).cage;
  const auto canvasPoints = points(canvas->surface);
  for (auto _ : state)
    benchmark::DoNotOptimize(computeGreenCoordinates(cage.mesh, canvasPoints));
  state.counters["cage_faces"] = double(cage.mesh.n_faces());
}

void BM_WholeSourcePreprocess(benchmark::State& state) {
  Stages stages;
  for (auto _ : state) {
    auto canvas = stages.canvas();
    const Cage cage = buildCage(*stages.map(canvas)).cage;
    benchmark::DoNotOptimize(computeGreenCoordinates(cage.mesh, points(canvas->surface)));
  }
}

// The source preprocessed once and the target sphere prepared: what a drag or a dab starts from.
struct Scene {
  Stages stages;
  std::shared_ptr<Canvas> canvas = stages.canvas();
  std::shared_ptr<Parameterization> source = stages.map(canvas);
  Cage cage = buildCage(*source).cage;
  GreenCoordinatesResult gc = computeGreenCoordinates(cage.mesh, points(canvas->surface));
  PreparedTarget target{std::make_shared<const Mesh>(test::icosphere(7))};
};

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Dragging the target canvas with the source preprocess cached: per move, the target DEM, the
// cage fit (factorization and source columns kept) and applying the Green coordinates to a
// painted region's vertices, as gc_warp does when given the region (apply_region_ms). Applying
// them to every canvas vertex, for a whole draft, is timed apart from the move (apply_ms). The
// target is a 163,842-vertex sphere whose PreparedTarget is kept between moves, as the dem node
// keeps it. Counters give each stage's mean time per move.
void BM_TargetMove(benchmark::State& state) {
  const Scene scene;
  const auto& [stages, canvas, source, cage, gc, target] = scene;
  const CageFitOptions fitOptions;
  const CageFitSolver solver(cage, fitOptions.constraintWeight);
  const SourceColumns columns(cage, *source);
  TargetDemOptions demOptions;
  demOptions.scale = 0.3;
  // A painted region: the canvas vertices within a disc of a fifth of the domain's width.
  std::vector<int> region;
  for (std::size_t v = 0; v < source->uv.size(); ++v)
    if (source->uv[v].norm() < 0.4) region.push_back(int(v));
  double demMs = 0, fitMs = 0, applyMs = 0, applyRegionMs = 0;
  std::size_t targetVertices = 0;
  int move = 0;
  for (auto _ : state) {
    // Small steps along the sphere, as a drag makes them.
    const double angle = 0.01 * (move++ % 20);
    demOptions.origin = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.3).normalized();
    auto start = std::chrono::steady_clock::now();
    TargetDemResult dem = targetExponentialMap(target, source->uv, demOptions);
    Parameterization targetParam;
    targetParam.canvas = std::make_shared<const Canvas>(std::move(dem.canvas));
    targetParam.uv = std::move(dem.uv);
    targetParam.normal = std::move(dem.normal);
    targetParam.origin = dem.origin;
    targetParam.scale = demOptions.scale;
    targetVertices = targetParam.uv.size();
    demMs += millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    const CageFitResult fitted = fitCage(cage, *source, targetParam, fitOptions, &solver, &columns);
    fitMs += millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(
        applyGreenCoordinates(gc.phi, gc.psi, cage.mesh, fitted.cage.mesh, region).data());
    applyRegionMs += millisecondsSince(start);
    state.PauseTiming();
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(
        applyGreenCoordinates(gc.phi, gc.psi, cage.mesh, fitted.cage.mesh).data());
    applyMs += millisecondsSince(start);
    state.ResumeTiming();
  }
  const auto perMove = benchmark::Counter::kAvgIterations;
  state.counters["dem_ms"] = benchmark::Counter(demMs, perMove);
  state.counters["fit_ms"] = benchmark::Counter(fitMs, perMove);
  state.counters["apply_ms"] = benchmark::Counter(applyMs, perMove);
  state.counters["apply_region_ms"] = benchmark::Counter(applyRegionMs, perMove);
  state.counters["region_points"] = double(region.size());
  state.counters["source_points"] = double(canvas->surface.n_vertices());
  state.counters["target_canvas"] = double(targetVertices);
  state.counters["cage_faces"] = double(cage.mesh.n_faces());
}

// Painting with the preprocess and the target cached, as the studio evaluates a dab: the ROI (its
// grid, coverage and locators kept), the membrane (hierarchy updated, warm start from the previous
// dab) and the stitch (into the previous result turned back into the target's outside part, as
// the node does with a result no one holds), on a 256^2 grid. Each iteration adds one dab of a
// stroke across the canvas; counters give each stage's mean time per dab.
void BM_LiveBrush(benchmark::State& state) {
  const Scene scene;
  const auto& [stages, canvas, source, cage, gc, target] = scene;
  TargetDemOptions demOptions;
  demOptions.scale = 0.3;
  demOptions.origin = Eigen::Vector3d(1, 0, 0.3).normalized();
  TargetDemResult dem = targetExponentialMap(target, source->uv, demOptions);
  Parameterization targetParam;
  targetParam.canvas = std::make_shared<const Canvas>(std::move(dem.canvas));
  targetParam.uv = std::move(dem.uv);
  targetParam.normal = std::move(dem.normal);
  targetParam.origin = dem.origin;
  targetParam.scale = demOptions.scale;
  const Cage fitted = fitCage(cage, *source, targetParam).cage;
  TriMesh draft = canvas->surface;
  const auto warped = applyGreenCoordinates(gc.phi, gc.psi, cage.mesh, fitted.mesh);
  for (auto v : draft.vertices())
    draft.set_point(v, {warped[std::size_t(v.idx())].x(), warped[std::size_t(v.idx())].y(),
                        warped[std::size_t(v.idx())].z()});

  RoiCoverage coverage = roiCoverage(*source, targetParam, RoiOptions{256});
  const StitchBase stitchBaseOfTarget = stitchBase(targetParam);
  const DomainLocator sourceLocator(*source), targetLocator(targetParam);
  MembraneLocations locations;
  Strokes strokes;
  MembraneOptions membraneOptions;
  membraneOptions.tolerance = 1e-6;  // the node's default
  double roiMs = 0, membraneMs = 0, stitchMs = 0;
  std::size_t regionVertices = 0, resultVertices = 0;
  TriMesh result;
  bool holdsOutside = false;
  int dab = 0;
  for (auto _ : state) {
    strokes.dabs.push_back({{-0.6 + 0.03 * dab, -0.2 + 0.01 * dab}, 0.15, false});
    ++dab;
    auto start = std::chrono::steady_clock::now();
    const RoiResult roi = paintRegion(strokes, *source, targetParam, coverage);
    roiMs += millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    const MembraneSetup setup = membraneSetup(roi.region, *source, draft, sourceLocator,
                                              targetLocator, MembraneContinuity::C1, &locations);
    MembraneResult solved = solveMembrane(setup.problem, membraneOptions);
    const Field2D offset = membraneField(roi.region, setup, solved.values);
    membraneOptions.initialGuess = std::move(solved.values);
    membraneOptions.hierarchy = solved.hierarchy;
    membraneMs += millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    if (holdsOutside) restoreOutside(*stitchBaseOfTarget.outside, result);
    const StitchResult stitched = stitchPasteInto(result, roi.region, *source, draft, &offset,
                                                  targetParam, &stitchBaseOfTarget, holdsOutside);
    holdsOutside = stitched.startsWithOutside;
    stitchMs += millisecondsSince(start);
    regionVertices = roi.region.sourceVertices.size();
    resultVertices = result.n_vertices();
  }
  const auto perDab = benchmark::Counter::kAvgIterations;
  state.counters["roi_ms"] = benchmark::Counter(roiMs, perDab);
  state.counters["membrane_ms"] = benchmark::Counter(membraneMs, perDab);
  state.counters["stitch_ms"] = benchmark::Counter(stitchMs, perDab);
  state.counters["region_vertices"] = double(regionVertices);
  state.counters["result_vertices"] = double(resultVertices);
}

// The clone graph of the live-brush and drag benchmarks, prepared, as if read from `name` in a
// temporary folder of that name. The target is a geodesic sphere of `targetResolution` segments
// per icosahedron edge: 10 r^2 + 2 vertices (128: 163,842; 316: 998,562; 707: 4,998,492).
Graph cloneGraph(const std::string& name, int targetResolution) {
  const auto dir = std::filesystem::temp_directory_path() / ("geobrush-" + name);
  std::filesystem::create_directories(dir);
  Graph graph = parseGraph(R"({
    "format": "geobrush-graph", "formatVersion": 1,
    "nodes": {
      "source_mesh": {"type": "geobrush.primitive", "typeVersion": 1,
        "params": {"shape": "plane", "size": 2.0, "resolution": 280, "relief": 0.02}},
      "source_canvas": {"type": "geobrush.canvas_grow", "typeVersion": 1,
        "params": {"origin": [0, 0, 0], "dabs": [[0, 0, 0, 0.9]]}},
      "source_map": {"type": "geobrush.gdem", "typeVersion": 1},
      "source_cage": {"type": "geobrush.cage_build", "typeVersion": 1},
      "target_mesh": {"type": "geobrush.primitive", "typeVersion": 1,
        "params": {"shape": "sphere"}},
      "target_map": {"type": "geobrush.dem", "typeVersion": 1,
        "params": {"origin": [0, 0, 1], "scale": 0.3}},
      "target_cage": {"type": "geobrush.cage_fit", "typeVersion": 1},
      "warp": {"type": "geobrush.gc_warp", "typeVersion": 1},
      "strokes": {"type": "geobrush.strokes", "typeVersion": 1},
      "roi_correct": {"type": "geobrush.roi_correct", "typeVersion": 1},
      "roi": {"type": "geobrush.roi", "typeVersion": 1},
      "membrane": {"type": "geobrush.membrane", "typeVersion": 1},
      "stitch": {"type": "geobrush.stitch", "typeVersion": 1}
    },
    "connections": [
      {"from": "source_mesh.mesh", "to": "source_canvas.mesh"},
      {"from": "source_canvas.canvas", "to": "source_map.canvas"},
      {"from": "source_map.parameterization", "to": "source_cage.parameterization"},
      {"from": "target_mesh.mesh", "to": "target_map.mesh"},
      {"from": "source_map.parameterization", "to": "target_map.source"},
      {"from": "source_cage.cage", "to": "target_cage.source_cage"},
      {"from": "source_map.parameterization", "to": "target_cage.source"},
      {"from": "target_map.parameterization", "to": "target_cage.target"},
      {"from": "source_canvas.canvas", "to": "warp.canvas"},
      {"from": "source_cage.cage", "to": "warp.source_cage"},
      {"from": "target_cage.target_cage", "to": "warp.target_cage"},
      {"from": "roi.region", "to": "warp.region"},
      {"from": "strokes.strokes", "to": "roi_correct.strokes"},
      {"from": "source_map.parameterization", "to": "roi_correct.source"},
      {"from": "roi_correct.strokes", "to": "roi.strokes"},
      {"from": "source_map.parameterization", "to": "roi.source"},
      {"from": "target_map.parameterization", "to": "roi.target"},
      {"from": "roi.region", "to": "membrane.region"},
      {"from": "source_map.parameterization", "to": "membrane.source"},
      {"from": "warp.draft", "to": "membrane.draft"},
      {"from": "target_map.parameterization", "to": "membrane.target"},
      {"from": "roi.region", "to": "stitch.region"},
      {"from": "source_map.parameterization", "to": "stitch.source"},
      {"from": "warp.draft", "to": "stitch.draft"},
      {"from": "target_map.parameterization", "to": "stitch.target"},
      {"from": "membrane.offset", "to": "stitch.offset"}]
  })",
                           dir / (name + ".json"));
  graph.nodes.at("target_mesh").params["resolution"] = targetResolution;
  prepareGraph(graph, test::registry());
  return graph;
}

// Per evaluation, each node's time that ran (not a cache hit), summed into `seconds`.
void addNodeTimes(const EvalReport& report, std::map<std::string, double>& seconds) {
  for (const NodeRun& run : report.runs)
    if (!run.cacheHit) seconds[run.node] += run.seconds;
}

// The summed node times as counters NODE_ms, the mean per benchmark iteration.
void setNodeCounters(benchmark::State& state, const std::map<std::string, double>& seconds) {
  for (const auto& [node, total] : seconds)
    state.counters[node + "_ms"] =
        benchmark::Counter(1000 * total, benchmark::Counter::kAvgIterations);
}

// The live brush as the studio runs it: a whole clone graph through the evaluator, preprocess
// cached, one dab appended to the strokes param per iteration and the paste evaluated. Unlike
// BM_LiveBrush this includes every node a dab reaches (strokes, ROI correction, the warp's
// partial draft) and the framework. The source is a 280^2 relief plane with a canvas of about
// 50k vertices, the target a geodesic sphere of argument 0's resolution (see cloneGraph).
// Counters: each node's mean time per dab, from the evaluator's report, and the median dab.
void BM_LiveBrushGraph(benchmark::State& state) {
  Graph graph = cloneGraph("live-brush-graph", int(state.range(0)));
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.targets = {"stitch"};
  std::vector<double> dabs = {-0.3, -0.1, 0.12, 1};
  graph.nodes.at("strokes").params["dabs"] = dabs;
  EvalReport first = evaluator.evaluate(graph, options);
  if (!first.ok) {
    state.SkipWithError(first.error.c_str());
    return;
  }
  std::map<std::string, double> seconds;
  std::vector<double> dabMs;
  std::size_t resultVertices = 0;
  int dab = 0;
  for (auto _ : state) {
    ++dab;
    dabs.insert(dabs.end(), {-0.3 + 0.02 * dab, -0.1 + 0.007 * dab, 0.12, 1});
    graph.nodes.at("strokes").params["dabs"] = dabs;
    const auto start = std::chrono::steady_clock::now();
    const EvalReport report = evaluator.evaluate(graph, options);
    dabMs.push_back(millisecondsSince(start));
    if (!report.ok) {
      state.SkipWithError(report.error.c_str());
      return;
    }
    addNodeTimes(report, seconds);
    state.PauseTiming();
    resultVertices = std::dynamic_pointer_cast<const Mesh>(evaluator.output("stitch", "mesh"))
                         ->surface.n_vertices();
    state.ResumeTiming();
  }
  setNodeCounters(state, seconds);
  std::sort(dabMs.begin(), dabMs.end());
  state.counters["dab_median_ms"] = dabMs[dabMs.size() / 2];
  state.counters["result_vertices"] = double(resultVertices);
  state.counters["canvas_vertices"] =
      double(std::dynamic_pointer_cast<const Canvas>(evaluator.output("source_canvas", "canvas"))
                 ->surface.n_vertices());
}

// Dragging the target canvas with a painted ROI, as the studio runs it: the clone graph of
// BM_LiveBrushGraph with a 12-dab stroke painted, its target canvas origin moved a step along the
// sphere per iteration and the paste evaluated. Every node downstream of the target canvas runs:
// the target DEM, the cage fit, the warp of the region's vertices, the ROI, the membrane and the
// stitch (on the base of each move's target canvas). 120 moves of
// 0.004 rad (0.48 rad, about 1.4 times the target canvas' radius). Counters: each node's mean
// time per move, from the evaluator's report, and the median, 90th percentile and largest move.
//
// Argument 0, 1: the target canvas also covers the source cage's columns (target_map.source_cage
// connected, as in the clone methods); 0: only the source map's disk and margin. Argument 1: the
// target sphere's resolution (see cloneGraph).
void BM_TargetMoveGraph(benchmark::State& state) {
  Graph graph = cloneGraph("target-move-graph", int(state.range(1)));
  if (state.range(0) == 1) {
    graph.connections.push_back({{"source_cage", "cage"}, {"target_map", "source_cage"}});
    prepareGraph(graph, test::registry());
  }
  Evaluator evaluator(test::registry());
  EvalOptions options;
  options.targets = {"stitch"};
  std::vector<double> dabs;
  for (int dab = 0; dab < 12; ++dab)
    dabs.insert(dabs.end(), {-0.3 + 0.04 * dab, -0.1 + 0.014 * dab, 0.12, 1});
  graph.nodes.at("strokes").params["dabs"] = dabs;
  auto moveTo = [&](int step) {
    const double angle = 0.004 * step;
    const Eigen::Vector3d origin =
        Eigen::Vector3d(std::sin(angle), 0.3 * std::sin(angle), std::cos(angle)).normalized();
    graph.nodes.at("target_map").params["origin"] = Vec3{origin.x(), origin.y(), origin.z()};
  };
  moveTo(0);
  if (const EvalReport first = evaluator.evaluate(graph, options); !first.ok) {
    state.SkipWithError(first.error.c_str());
    return;
  }
  std::map<std::string, double> seconds;
  std::vector<double> moveMs;
  int step = 0;
  for (auto _ : state) {
    moveTo(++step);
    const auto start = std::chrono::steady_clock::now();
    const EvalReport report = evaluator.evaluate(graph, options);
    moveMs.push_back(millisecondsSince(start));
    if (!report.ok) {
      state.SkipWithError(report.error.c_str());
      return;
    }
    addNodeTimes(report, seconds);
  }
  setNodeCounters(state, seconds);
  // The moves that outgrow the stitch's open part rebuild it: the mean hides how often.
  std::sort(moveMs.begin(), moveMs.end());
  state.counters["move_median_ms"] = moveMs[moveMs.size() / 2];
  state.counters["move_p90_ms"] = moveMs[moveMs.size() * 9 / 10];
  state.counters["move_max_ms"] = moveMs.back();
}

}  // namespace

// Targets of 164k, 1M and 5M vertices: a dab's cost should follow the region, not the target.
BENCHMARK(BM_LiveBrushGraph)
    ->Arg(128)
    ->Arg(316)
    ->Arg(707)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(30);
BENCHMARK(BM_TargetMoveGraph)
    ->Args({0, 128})
    ->Args({1, 128})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(120);
BENCHMARK(BM_TargetMoveGraph)
    ->Args({1, 316})
    ->Args({1, 707})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(30);
BENCHMARK(BM_LiveBrush)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(30);
BENCHMARK(BM_TargetMove)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly();
BENCHMARK(BM_CanvasGrow)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_GeneralizedDem)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_CageBuild)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_GreenCoordinates)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_WholeSourcePreprocess)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
