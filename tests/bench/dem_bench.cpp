// The target DEM as run on every drag of the target canvas: a 163k-vertex subdivided sphere and
// a source canvas whose required disk spans about 10% of the sphere's circumference.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "dem.hpp"

namespace {

using geobrush::TriMesh;

// An icosahedron split `levels` times, its vertices pushed onto the unit sphere.
geobrush::MeshPtr icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& x : p)
    x.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      return mid[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& [a, b, c] : f) {
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(next);
  }
  TriMesh mesh;
  for (const auto& x : p)
    mesh.add_vertex({x.x(), x.y(), x.z()});
  for (const auto& [a, b, c] : f)
    mesh.add_face(TriMesh::VertexHandle(a), TriMesh::VertexHandle(b), TriMesh::VertexHandle(c));
  return std::make_shared<const geobrush::Mesh>(std::move(mesh));
}

void BM_TargetDem(benchmark::State& state) {
  static const geobrush::MeshPtr sphere = icosphere(7);  // 163842 vertices
  // A 40 x 40 source canvas over [-1, 1]^2.
  std::vector<Eigen::Vector2d> source;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i)
      source.emplace_back(-1 + i / 20.0, -1 + j / 20.0);
  geobrush::TargetDemOptions o;
  o.origin = Eigen::Vector3d(0.3, 0.8, 0.5).normalized();
  o.scale = 0.35;  // required radius 1.77 x 0.35 = 0.62 on the unit sphere
  std::size_t vertices = 0;
  for (auto _ : state) {
    const auto dem = geobrush::targetExponentialMap(sphere, source, o);
    vertices = dem.uv.size();
    benchmark::DoNotOptimize(dem.uv.data());
  }
  state.counters["canvas_vertices"] = static_cast<double>(vertices);
  state.counters["mesh_vertices"] = static_cast<double>(sphere->surface.n_vertices());
}
BENCHMARK(BM_TargetDem)->Unit(benchmark::kMillisecond)->Repetitions(7)->ReportAggregatesOnly();

}  // namespace
