// Loading a mesh file: where a graph's geometry comes from.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct LoadMeshOptions {
  // Split faces that make an edge or vertex non-manifold off onto their own copies of their
  // vertices, with a warning, instead of failing.
  bool repair = false;
  // The reading's progress (MeshReadOptions::progress).
  std::function<void(double)> progress;
};

struct LoadMeshResult {
  MeshPtr mesh;
  std::vector<std::string> warnings;  // what was repaired, dropped or triangulated, per file
};

// Reads an OBJ, PLY, OFF or STL file as readMesh does (see mesh_io.hpp). Throws MeshError, whose
// message names the file and the cause, also when `path` is empty.
LoadMeshResult loadMesh(const std::filesystem::path& path, const LoadMeshOptions& options = {});

}  // namespace geobrush
