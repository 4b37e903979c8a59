// Reading, checking and writing meshes (OpenMesh IO underneath).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// A mesh file that cannot be used; the message names the file and the cause.
class MeshError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct MeshReadOptions {
  // Faces that make an edge non-manifold are split off onto their own copies
  // of their vertices (with a warning) instead of failing.
  bool repairNonManifold = false;
};

struct MeshReadResult {
  std::shared_ptr<Mesh> mesh;
  std::vector<std::string> warnings;  // what was repaired or dropped
};

// OBJ, PLY, OFF or STL by extension. Throws MeshError for a missing or
// unreadable file, an unknown format, no faces, non-finite coordinates, or
// (unless repaired) non-manifold edges.
MeshReadResult readMesh(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Writes by extension (OBJ, PLY, OFF, STL) to exactly `path` (no temporary
// file: callers make it atomic). Throws MeshError.
void writeMesh(const Mesh& mesh, const std::filesystem::path& path);

struct MeshStats {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t boundaryLoops = 0;
  std::size_t components = 0;
  std::size_t nonFiniteVertices = 0;
  std::size_t isolatedVertices = 0;
  int eulerCharacteristic = 0;
};
MeshStats meshStats(const TriMesh& mesh);

}  // namespace geobrush
