#include "geobrush/mesh_io.hpp"

#include "atomic_file.hpp"

#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <new>
#include <numeric>

#include "geobrush/text.hpp"
#include "mesh_read.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;
using OpenMesh::Vec3d;

MeshError fileError(const fs::path& path, const std::string& cause) {
  return MeshError(quotePath(path) + ": " + cause);
}

using meshread::count;
using meshread::formatPoint;
using meshread::isFinite;

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// OpenMesh's readers and writers are process-wide singletons that keep per-call state, and its
// log streams are process-wide too. Every use of them holds this session: one at a time, with the
// streams muted so that the user sees our messages (which name the file) instead of OpenMesh's.
class OpenMeshSession {
 public:
  OpenMeshSession() : lock_(mutex()) {
    for (std::size_t i = 0; i < kStreams.size(); ++i) {
      wasEnabled_[i] = kStreams[i]().is_enabled();
      kStreams[i]().disable();
    }
  }
  ~OpenMeshSession() {
    for (std::size_t i = 0; i < kStreams.size(); ++i) {
      // Flushing while muted discards a message that did not end its line yet, which would
      // otherwise come out with the next one after unmuting.
      kStreams[i]().flush();
      if (wasEnabled_[i]) kStreams[i]().enable();
    }
  }
  OpenMeshSession(const OpenMeshSession&) = delete;
  OpenMeshSession& operator=(const OpenMeshSession&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex instance;
    return instance;
  }
  static constexpr std::array<OpenMesh::mostream& (*)(), 3> kStreams{&omerr, &omlog, &omout};
  std::lock_guard<std::mutex> lock_;
  std::array<bool, 3> wasEnabled_{};
};

void writeObj(const TriMesh& mesh, std::ostream& out) {
  constexpr std::size_t kChunk = 1 << 20;
  std::string buffer;
  buffer.reserve(kChunk + 256);
  const auto flushIfFull = [&] {
    if (buffer.size() < kChunk) return;
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    buffer.clear();
  };
  buffer += "# " + count(mesh.n_vertices(), "vertex", "vertices") + ", " +
            count(mesh.n_faces(), "face", "faces") + "\n";
  std::array<char, 32> number{};
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {
    const auto& point = mesh.point(TriMesh::VertexHandle(static_cast<int>(i)));
    buffer += 'v';
    for (int k = 0; k < 3; ++k) {
      // The shortest text that reads back to the same double.
      buffer += ' ';
      buffer.append(number.data(), std::to_chars(number.begin(), number.end(), point[k]).ptr);
    }
    buffer += '\n';
    flushIfFull();
  }
  for (auto face : mesh.faces()) {
    buffer += 'f';
    for (auto vertex : mesh.fv_range(face)) {
      buffer += ' ';
      buffer.append(number.data(),
                    std::to_chars(number.begin(), number.end(), vertex.idx() + 1).ptr);
    }
    buffer += '\n';
    flushIfFull();
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

// A mesh file must be a regular file (or a link to one): a FIFO or a device would block or never
// end.
void checkIsFile(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw fileError(path, "cannot be accessed: " + ec.message());
  if (!fs::exists(status)) throw fileError(path, "no such file");
  if (fs::is_directory(status)) throw fileError(path, "is a folder, not a mesh file");
  if (!fs::is_regular_file(status))
    throw fileError(path, "is not a regular file (a device, FIFO or socket), not a mesh file");
}

std::string readBytes(const fs::path& path) {
  checkIsFile(path);
  std::error_code ec;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, std::string("cannot be opened: ") + std::strerror(errno));
  const auto size = fs::file_size(path, ec);
  if (ec) throw fileError(path, "cannot be read: " + ec.message());
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (in.bad() || std::size_t(in.gcount()) != bytes.size())
    throw fileError(path, "cannot be read: " + std::string(std::strerror(errno)));
  return bytes;
}

// Why faces were dropped, e.g. "1 with a repeated vertex, 2 with a vertex index out of range".
std::string dropReasons(MeshFormat format, const meshread::ImportCounts& counts) {
  std::string reasons;
  const auto add = [&](std::size_t n, std::string_view why) {
    if (n > 0) reasons += (reasons.empty() ? "" : ", ") + std::to_string(n) + std::string(why);
  };
  add(counts.tooFewCorners, " with fewer than 3 corners");
  // STL lists positions, so a vertex repeats where corners share a position.
  add(counts.repeatedVertex,
      format == MeshFormat::Stl ? " with corners at one position" : " with a repeated vertex");
  add(counts.badIndex, " with a vertex index out of range");
  return reasons;
}

MeshReadResult checkImport(const fs::path& path, MeshFormat format, TriMesh surface,
                           const meshread::ImportCounts& counts, const MeshReadOptions& options) {
  const std::size_t inFile = counts.offered;
  if (inFile == 0) {
    throw fileError(
        path, surface.n_vertices() == 0
                  ? "holds no vertices and no faces"
                  : "has " + count(surface.n_vertices(), "vertex", "vertices") + " but no faces");
  }

  MeshReadResult result;
  const std::size_t dropped = counts.dropped();
  if (dropped == inFile) {
    throw fileError(path, "none of its " + count(inFile, "face", "faces") +
                              " is usable: " + dropReasons(format, counts));
  }
  if (dropped > 0) {
    result.warnings.push_back(quotePath(path) + ": dropped " + std::to_string(dropped) + " of " +
                              count(inFile, "face", "faces") + ": " + dropReasons(format, counts));
  }

  if (counts.nonManifold > 0) {
    const std::string first =
        "the first is face " + std::to_string(counts.firstNonManifold) + " of the file, 0-based";
    const std::string faces = count(counts.nonManifold, "face", "faces");
    const std::string problem =
        " would make an edge or vertex non-manifold or flip the orientation (" + first + ")";
    if (!options.repairNonManifold)
      throw fileError(path,
                      faces + problem + "; set repair to split them off onto their own vertices");
    result.warnings.push_back(quotePath(path) + ": repaired " + faces + " that" + problem +
                              ": split off onto their own copies of their vertices, " +
                              count(3 * counts.nonManifold, "vertex", "vertices") + " added");
  }

  if (counts.triangulated > 0) {
    result.warnings.push_back(
        quotePath(path) + ": triangulated " + count(counts.triangulated, "polygon", "polygons") +
        " with more than 3 corners into " + count(counts.triangles, "triangle", "triangles") +
        " (fans from each first corner)");
  }

  result.mesh = std::make_shared<Mesh>(std::move(surface));
  return result;
}

meshread::PolygonSoup readSoup(const meshread::Source& source, MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      return meshread::readObj(source);
    case MeshFormat::Ply:
      return meshread::readPly(source);
    case MeshFormat::Off:
      return meshread::readOff(source);
    case MeshFormat::Stl:
      return meshread::readStl(source);
  }
  throw source.error("unknown mesh format");
}

}  // namespace

std::optional<MeshFormat> meshFormatFromPath(const fs::path& path) {
  const std::string extension = lowercase(path.extension().string());
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".stl") return MeshFormat::Stl;
  return std::nullopt;
}

std::string_view toString(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      return "OBJ";
    case MeshFormat::Ply:
      return "PLY";
    case MeshFormat::Off:
      return "OFF";
    case MeshFormat::Stl:
      return "STL";
  }
  return "?";
}

MeshReadResult readMesh(const fs::path& path, const MeshReadOptions& options) {
  checkIsFile(path);
  const auto format = meshFormatFromPath(path);
  if (!format) {
    throw fileError(path, "unknown mesh format " + quoteText(path.extension().string()) +
                              " (supported: .obj, .ply, .off, .stl)");
  }
  const std::string bytes = readBytes(path);
  if (options.progress) options.progress(0.2);
  return readMeshBytes(bytes, *format, path, options);
}

MeshReadResult readMeshBytes(std::string_view bytes, MeshFormat format, const fs::path& name,
                             const MeshReadOptions& options) {
  try {
    const auto report = [&](double fraction) {
      if (options.progress) options.progress(fraction);
    };
    const meshread::PolygonSoup soup = readSoup({name, bytes}, format);
    report(0.7);
    TriMesh surface;
    const meshread::ImportCounts counts = meshread::linkSoup(soup, surface);
    report(0.9);
    MeshReadResult result = checkImport(name, format, std::move(surface), counts, options);
    report(1.0);
    result.warnings.insert(result.warnings.begin(), soup.warnings.begin(), soup.warnings.end());
    return result;
  } catch (const std::bad_alloc&) {
    throw fileError(name, "not enough memory to read its " + count(bytes.size(), "byte", "bytes"));
  }
}

MeshReadResult meshFromArrays(std::span<const double> positions,
                              std::span<const std::int64_t> triangles, const std::string& name,
                              const MeshReadOptions& options) {
  const auto fail = [&](const std::string& cause) { return fileError(name, cause); };
  if (positions.size() % 3 != 0 || triangles.size() % 3 != 0)
    throw fail("expected 3 coordinates per vertex and 3 vertex indices per triangle");
  meshread::PolygonSoup soup;
  soup.points.reserve(positions.size() / 3);
  for (std::size_t v = 0; v < positions.size(); v += 3) {
    const Vec3d p(positions[v], positions[v + 1], positions[v + 2]);
    if (!isFinite(p))
      throw fail("vertex " + std::to_string(v / 3) + " has a non-finite coordinate " +
                 formatPoint(p));
    soup.points.push_back(p);
  }
  const auto vertexCount = std::int64_t(soup.points.size());
  for (std::size_t t = 0; t < triangles.size(); t += 3) {
    const std::int64_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    for (const std::int64_t index : {a, b, c})
      if (index < 0 || index >= vertexCount)
        throw fail("triangle " + std::to_string(t / 3) + " names vertex " + std::to_string(index) +
                   " of " + std::to_string(vertexCount));
    if (a == b || b == c || c == a)
      throw fail("triangle " + std::to_string(t / 3) + " repeats a vertex");
    for (const std::int64_t index : {a, b, c})
      soup.addCorner(index);
    soup.endPolygon();
  }
  TriMesh surface;
  const meshread::ImportCounts counts = meshread::linkSoup(soup, surface);
  return checkImport(name, MeshFormat::Obj, std::move(surface), counts, options);
}

std::optional<std::string> unwritableReason(const TriMesh& mesh, MeshFormat format) {
  const double limit = format == MeshFormat::Obj ? std::numeric_limits<double>::max()
                                                 : std::numeric_limits<float>::max();
  for (auto vertex : mesh.vertices()) {
    const Vec3d& p = mesh.point(vertex);
    const std::string which = "vertex " + std::to_string(vertex.idx()) + " (0-based)";
    if (!isFinite(p)) return which + " has a non-finite coordinate " + formatPoint(p);
    if (std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) > limit) {
      return which + " has a coordinate beyond the 32-bit float range of " +
             std::string(toString(format)) + " " + formatPoint(p);
    }
  }
  return std::nullopt;
}

void writeMesh(const Mesh& mesh, const fs::path& path, std::optional<MeshFormat> format) {
  if (!format) format = meshFormatFromPath(path);
  if (!format) {
    throw fileError(path, "unknown mesh format '" + path.extension().string() +
                              "' (supported: .obj, .ply, .off, .stl)");
  }
  if (const auto reason = unwritableReason(mesh.surface, *format))
    throw fileError(path, "not written: " + *reason);

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw fileError(path, std::string("cannot be created: ") + std::strerror(errno));
  bool written = true;
  if (*format == MeshFormat::Obj) {
    writeObj(mesh.surface, out);
  } else {
    // STL holds 32-bit floats either way, and binary is its common, compact form; PLY and OFF
    // stay text. 17 digits print each 32-bit value exactly.
    const OpenMesh::IO::Options io =
        *format == MeshFormat::Stl ? OpenMesh::IO::Options::Binary : OpenMesh::IO::Options::Default;
    OpenMeshSession session;
    written = OpenMesh::IO::write_mesh(mesh.surface, out, lowercase(std::string(toString(*format))),
                                       io, 17);
  }
  out.close();
  if (!written || !out) {
    const std::string cause = std::strerror(errno);
    std::error_code ec;
    fs::remove(path, ec);
    throw fileError(path, written
                              ? "writing failed: " + cause
                              : "OpenMesh could not write it as " + std::string(toString(*format)));
  }
}

void writeMeshFile(const Mesh& mesh, const fs::path& path) {
  const auto format = meshFormatFromPath(path);
  if (!format)
    throw fileError(path, "unknown mesh format " + quoteText(path.extension().string()) +
                              " (supported: .obj, .ply, .off, .stl)");
  try {
    writeFileAtomically(path, [&](const fs::path& tmp) { writeMesh(mesh, tmp, format); });
  } catch (const MeshError&) {
    throw;
  } catch (const std::exception& e) {
    throw MeshError(e.what());
  }
}

MeshStats meshStats(const TriMesh& mesh) {
  MeshStats stats;
  stats.vertices = mesh.n_vertices();
  stats.faces = mesh.n_faces();
  stats.eulerCharacteristic = static_cast<int>(mesh.n_vertices()) -
                              static_cast<int>(mesh.n_edges()) + static_cast<int>(mesh.n_faces());

  std::vector<char> visited(mesh.n_halfedges(), 0);
  for (auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || visited[start.idx()]) continue;
    ++stats.boundaryLoops;
    for (auto h = start; !visited[h.idx()]; h = mesh.next_halfedge_handle(h))
      visited[h.idx()] = 1;
  }

  // Union-find over vertices, joined through faces.
  std::vector<int> parent(mesh.n_vertices());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[v] != v)
      v = parent[v] = parent[parent[v]];
    return v;
  };
  for (auto face : mesh.faces()) {
    const int first = root(face.halfedge().to().idx());
    for (auto vertex : mesh.fv_range(face))
      parent[root(vertex.idx())] = first;
  }
  for (auto vertex : mesh.vertices()) {
    if (!isFinite(mesh.point(vertex))) ++stats.nonFiniteVertices;
    if (mesh.is_isolated(vertex))
      ++stats.isolatedVertices;
    else if (root(vertex.idx()) == vertex.idx())
      ++stats.components;
  }
  return stats;
}

}  // namespace geobrush
