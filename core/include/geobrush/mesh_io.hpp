// Reading, checking and writing meshes.
//
// PLY, OFF and STL go through OpenMesh IO. OBJ, the format of the shipped meshes and of saved
// results, is read and written here: OpenMesh 9.0's readers and writers pass every point through
// 32-bit floats, and an OBJ round trip must be exact. So OBJ keeps full double precision (written
// as the shortest decimal that reads back to the same double), while PLY, OFF and STL hold
// 32-bit float coordinates (STL by definition, PLY and OFF through OpenMesh).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// A mesh file that cannot be used; the message names the file and the cause.
class MeshError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class MeshFormat { Obj, Ply, Off, Stl };

// The format named by the extension of `path` (.obj, .ply, .off, .stl in any letter case), or
// nothing.
std::optional<MeshFormat> meshFormatFromPath(const std::filesystem::path& path);
// "OBJ", "PLY", "OFF" or "STL".
std::string_view toString(MeshFormat format);

struct MeshReadOptions {
  // Faces that OpenMesh cannot attach to their neighbours (a third face on an edge, a face
  // oriented against its neighbour, a vertex whose faces cannot form fans) are split off onto
  // their own copies of their vertices (with a warning) instead of failing. Their faces, edges
  // and vertices keep OpenMesh's fixed_nonmanifold status bit.
  bool repairNonManifold = false;
};

struct MeshReadResult {
  std::shared_ptr<Mesh> mesh;
  std::vector<std::string> warnings;  // what was repaired, dropped or triangulated
};

// Reads OBJ, PLY, OFF or STL (by extension) into a triangle mesh, keeping the file's vertex
// order (STL has no shared vertices: OpenMesh merges corners at equal positions, in order of
// first use). Polygons are fan-triangulated from their first corner, with a warning. Faces with
// fewer than 3 corners, a repeated vertex or a vertex index out of range are dropped with a
// warning. Throws MeshError, naming the file, for a missing or unreadable file, an unknown
// extension, no usable faces, a non-finite coordinate (naming the first such vertex), or
// (unless repaired) faces that make an edge or vertex non-manifold. Vertex colours are not read.
MeshReadResult readMesh(const std::filesystem::path& path, const MeshReadOptions& options = {});

// Why `format` cannot hold `mesh` so that it reads back: a non-finite coordinate, or one beyond
// the 32-bit float range in PLY, OFF and STL (naming the first such vertex); or nothing.
std::optional<std::string> unwritableReason(const TriMesh& mesh, MeshFormat format);

// Writes points and faces (not colours) to exactly `path` (no temporary file: callers make it
// atomic), in `format`, or in the format named by the extension of `path` when no format is
// given; pass the format when `path` is a temporary stand-in for the real file. Throws MeshError
// naming `path` for an unknown format, an unwritableReason, or a failed write, and then leaves no
// file at `path`.
void writeMesh(const Mesh& mesh, const std::filesystem::path& path,
               std::optional<MeshFormat> format = std::nullopt);

struct MeshStats {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t boundaryLoops = 0;
  // Pieces of surface connected through shared vertices; isolated vertices are not pieces.
  std::size_t components = 0;
  std::size_t nonFiniteVertices = 0;
  std::size_t isolatedVertices = 0;  // vertices of no face
  // V - E + F: 2 - 2 genus - boundary loops, summed over the components.
  int eulerCharacteristic = 0;
};
MeshStats meshStats(const TriMesh& mesh);

}  // namespace geobrush
