// Saving a mesh to a file: where a graph's result goes.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"
#include "geobrush/mesh_io.hpp"

namespace geobrush {

struct SaveMeshOptions {
  // The file to be written in the end. Its extension (.obj, .ply, .off or .stl, in any letter
  // case) picks the format, and its folder must exist.
  std::filesystem::path destination;
};

struct SaveMeshPlan {
  MeshFormat format = MeshFormat::Obj;
  // What the file will not hold, each naming the destination: vertex colours (no format gets
  // them), precision (PLY, OFF and STL hold 32-bit floats), isolated vertices and vertices that
  // share a position (STL keeps only triangle corners, and reading merges equal ones).
  std::vector<std::string> warnings;
};

// Checks, before anything is written, that `mesh` can be saved to the destination, and says in
// which format and what it will lose. The file itself is then written by
// writeMesh(mesh, file, plan.format), where `file` may be a temporary stand-in for the
// destination. Throws MeshError naming the destination for an empty path, an unknown extension,
// a missing folder, a folder in the file's place, or a coordinate the format cannot hold
// (non-finite, or beyond the 32-bit float range in PLY, OFF and STL).
SaveMeshPlan planMeshSave(const Mesh& mesh, const SaveMeshOptions& options);

}  // namespace geobrush
