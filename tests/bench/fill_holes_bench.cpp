// fill_holes against CGAL 5.5's triangulate_refine_and_fair_hole (C1, density sqrt 2) on the
// same holes: the cut cases, the scanned bunny's five holes, the CAD part's four holes,
// and growing holes cut from an icosphere for the time at 2k new vertices and more. Counters:
// new vertices, and for the cut cases the mean distance of the new vertices to the removed patch
// over the bounding-box diagonal.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include "cgal_reference.hpp"
#include "fill_holes.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

struct HoleCase {
  const char* name;
  TriMesh holed;
  TriMesh truth;  // empty: no ground truth
  FillHolesOptions options;
};

TriMesh load(const std::filesystem::path& path) {
  return readMesh(path).mesh->surface;
}

// An icosphere of 5 levels with the cap z > 1 - depth removed.
TriMesh sphereWithCap(double depth) {
  TriMesh mesh = test::icosphere(6);
  for (auto f : mesh.faces()) {
    double z = 0.0;
    for (auto v : mesh.fv_range(f))
      z += mesh.point(v)[2] / 3.0;
    if (z > 1.0 - depth) mesh.delete_face(f, true);
  }
  mesh.garbage_collection();
  return mesh;
}

const HoleCase& holeCase(int index) {
  static const std::vector<HoleCase> cases = [] {
    std::vector<HoleCase> list;
    for (const char* name : {"bunny_small_back", "nefertiti_forehead", "nefertiti_back"}) {
      const std::string base = name;
      list.push_back({name,
                      load(test::meshDir() / "cases" / (base + "_hole.obj")),
                      load(test::meshDir() / "cases" / (base + "_removed_patch.obj")),
                      {}});
    }
    list.push_back({"bunny_scan", load(test::meshPath("bunny_scan.obj")), {}, {}});
    list.push_back({"mech_holes_shark", load(test::meshPath("mech_holes_shark.obj")), {}, {}});
    for (double depth : {0.2, 0.5, 1.0})
      list.push_back({"icosphere6_cap", sphereWithCap(depth), {}, {}});
    return list;
  }();
  return cases[std::size_t(index)];
}

std::vector<Eigen::Vector3d> addedPoints(const TriMesh& filled, const TriMesh& holed) {
  std::vector<Eigen::Vector3d> points;
  for (int v = int(holed.n_vertices()); v < int(filled.n_vertices()); ++v) {
    const auto& p = filled.point(TriMesh::VertexHandle(v));
    points.emplace_back(p[0], p[1], p[2]);
  }
  return points;
}

void report(benchmark::State& state, const HoleCase& hole, const TriMesh& filled) {
  state.SetLabel(hole.name);
  state.counters["new_vertices"] = double(filled.n_vertices() - hole.holed.n_vertices());
  if (hole.truth.n_faces() > 0)
    state.counters["mean_dist_over_diag"] =
        test::cgalDistances(addedPoints(filled, hole.holed), hole.truth).mean /
        boundingDiagonal(hole.holed);
}

void BM_FillHoles(benchmark::State& state) {
  const HoleCase& hole = holeCase(int(state.range(0)));
  TriMesh filled;
  for (auto _ : state)
    filled = fillHoles(hole.holed, hole.options).mesh;
  report(state, hole, filled);
}

void BM_CgalFillHoles(benchmark::State& state) {
  const HoleCase& hole = holeCase(int(state.range(0)));
  TriMesh filled;
  for (auto _ : state)
    filled = test::cgalFillHoles(hole.holed, 1).mesh;
  report(state, hole, filled);
}

BENCHMARK(BM_FillHoles)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CgalFillHoles)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace geobrush
