#include "load_mesh.hpp"

#include "geobrush/mesh_io.hpp"

namespace geobrush {

LoadMeshResult loadMesh(const std::filesystem::path& path, const LoadMeshOptions& options) {
  if (path.empty()) throw MeshError("no file given");
  MeshReadOptions read;
  read.repairNonManifold = options.repair;
  read.progress = options.progress;
  MeshReadResult loaded = readMesh(path, read);
  return {std::move(loaded.mesh), std::move(loaded.warnings)};
}

}  // namespace geobrush
