// Reading, checking and writing meshes.
//
// Every format is read here (core/src/read_*.cpp), not by OpenMesh's readers: a file from another
// tool may declare any size and hold anything, and each reader checks what a file declares
// against what it holds before allocating, ends in a time linear in the file's size, and names
// the file and the place of any problem. OBJ keeps full double precision both ways (written as
// the shortest decimal that reads back to the same double); PLY keeps each property's declared
// type (float or double); OFF and STL hold 32-bit floats. PLY, OFF and STL are written through
// OpenMesh, whose writers pass every point through 32-bit floats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
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
  // Called with the share of the work done as each stage ends: the file read, its polygons
  // parsed, the mesh linked and checked. It may throw to stop reading (a cancelled evaluation).
  std::function<void(double)> progress;
};

struct MeshReadResult {
  std::shared_ptr<Mesh> mesh;
  std::vector<std::string> warnings;  // what was repaired, dropped or triangulated
};

// Reads OBJ, PLY (ASCII or binary), OFF (text or binary) or STL (ASCII or binary), by extension,
// into a triangle mesh, keeping the file's vertex order (STL has no shared vertices: corners at
// equal positions become one vertex, in order of first use). Polygons are fan-triangulated from
// their first corner, with a warning. Faces with fewer than 3 corners, a repeated vertex or a
// vertex index out of range are dropped with a warning. Throws MeshError, naming the file (and
// the line or byte where it applies), for a missing file or one that is not a regular file, an
// unknown extension, a malformed or truncated file, a count the file's size cannot hold, no
// usable faces, a non-finite coordinate (naming the first such vertex), or (unless repaired) faces
// that make an edge or vertex non-manifold. Vertex colours are not read.
MeshReadResult readMesh(const std::filesystem::path& path, const MeshReadOptions& options = {});

// readMesh of a file's bytes, held in memory; `name` is the file named in messages.
MeshReadResult readMeshBytes(std::string_view bytes, MeshFormat format,
                             const std::filesystem::path& name,
                             const MeshReadOptions& options = {});

// A mesh from arrays held in memory (e.g. NumPy's, from Python): `positions` holds x, y, z per
// vertex and `triangles` three 0-based vertex indices per face; `name` names them in messages.
// Throws MeshError, naming the vertex or triangle, for a length that is not a multiple of 3, a
// non-finite coordinate, an index out of range or a triangle with a repeated vertex, and, as
// readMesh does, for no triangles or (unless repaired) triangles that make an edge or vertex
// non-manifold.
MeshReadResult meshFromArrays(std::span<const double> positions,
                              std::span<const std::int64_t> triangles, const std::string& name,
                              const MeshReadOptions& options = {});

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

// writeMesh in the format named by the extension, atomically: the file at `path` is replaced
// only by the complete new one (a symbolic link there stays and its file is replaced). Throws
// MeshError naming `path`; nothing is written then.
void writeMeshFile(const Mesh& mesh, const std::filesystem::path& path);

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
