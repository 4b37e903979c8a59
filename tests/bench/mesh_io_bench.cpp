// Reading mesh files: readMesh (GeoBrush's readers, the faces linked at once) against OpenMesh's
// own readers (add_face per face) on the same files, in one process. The scattered fan is the case
// add_face handles in quadratic time: many faces around one vertex, in shuffled order.
#include <benchmark/benchmark.h>

#include <cmath>
#include <fstream>
#include <random>

#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;

// A disc of n triangles around vertex 1, listed in shuffled order.
fs::path scatteredFan(int n) {
  const fs::path path = test::tempDir("bench-fan-" + std::to_string(n)) / "fan.obj";
  std::ofstream out(path);
  out << "v 0 0 0\n";
  for (int i = 0; i < n; ++i)
    out << "v " << std::cos(2 * M_PI * i / n) << " " << std::sin(2 * M_PI * i / n) << " 0\n";
  std::vector<int> order(std::size_t(n), 0);
  for (int i = 0; i < n; ++i)
    order[std::size_t(i)] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937(1));
  for (int i : order)
    out << "f 1 " << i + 2 << " " << (i + 1) % n + 2 << "\n";
  return path;
}

// nefertiti.obj (35,002 vertices) written as `extension`.
fs::path nefertitiAs(const std::string& extension) {
  const fs::path path = test::tempDir("bench-nefertiti-" + extension) / ("nefertiti." + extension);
  writeMesh(*readMesh(test::meshPath("nefertiti.obj")).mesh, path);
  return path;
}

const fs::path& file(int which) {
  static const std::vector<fs::path> files = {test::meshPath("nefertiti.obj"), nefertitiAs("ply"),
                                              nefertitiAs("stl"), scatteredFan(5000),
                                              scatteredFan(20000)};
  return files[std::size_t(which)];
}

void label(benchmark::State& state, const TriMesh& mesh) {
  state.SetLabel(file(int(state.range(0))).filename().string() + ", " +
                 std::to_string(mesh.n_faces()) + " faces");
}

void BM_ReadMesh(benchmark::State& state) {
  const fs::path& path = file(int(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(readMesh(path));
  label(state, readMesh(path).mesh->surface);
}

void BM_OpenMeshRead(benchmark::State& state) {
  const fs::path& path = file(int(state.range(0)));
  TriMesh mesh;
  for (auto _ : state) {
    mesh.clean();
    if (!OpenMesh::IO::read_mesh(mesh, path.string()))
      state.SkipWithError("OpenMesh cannot read it");
  }
  label(state, mesh);
}

// 0: nefertiti.obj, 1: .ply, 2: .stl, 3: a fan of 5,000 faces, 4: of 20,000 faces.
BENCHMARK(BM_ReadMesh)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OpenMeshRead)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace geobrush
