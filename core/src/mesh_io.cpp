#include "geobrush/mesh_io.hpp"

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
#include <numeric>

namespace geobrush {
namespace {

namespace fs = std::filesystem;
using OpenMesh::Vec3d;

std::string quoted(const fs::path& path) {
  std::string text = "'";
  text += path.string();
  text += '\'';
  return text;
}

MeshError fileError(const fs::path& path, const std::string& cause) {
  return MeshError(quoted(path) + ": " + cause);
}

std::string count(std::size_t n, std::string_view one, std::string_view many) {
  return std::to_string(n) + " " + std::string(n == 1 ? one : many);
}

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool isFinite(const Vec3d& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

std::string formatPoint(const Vec3d& p) {
  std::string text = "(";
  std::array<char, 32> number{};
  for (int k = 0; k < 3; ++k) {
    if (k > 0) text += ", ";
    text.append(number.data(), std::to_chars(number.begin(), number.end(), p[k]).ptr);
  }
  return text + ")";
}

// `line` is the 1-based line of a text file, or 0 where there is none.
MeshError nonFiniteError(const fs::path& path, std::string_view element, std::size_t index,
                         std::size_t line, const std::string& detail) {
  std::string where = std::string(element) + " " + std::to_string(index) + " (0-based";
  if (line > 0) where += ", line " + std::to_string(line);
  return fileError(path, where + ") has a non-finite coordinate: " + detail);
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

// What happened to each polygon of the file on its way into the mesh; OpenMesh's readers only
// print it.
struct ImportCounts {
  std::size_t offered = 0;  // polygons the reader handed over
  std::size_t tooFewCorners = 0;
  std::size_t badIndex = 0;
  std::size_t repeatedVertex = 0;
  std::size_t triangulated = 0;      // polygons with more than 3 corners
  std::size_t triangles = 0;         // made from those polygons
  std::size_t nonManifold = 0;       // triangles split off onto copies of their vertices
  std::size_t firstNonManifold = 0;  // polygon index in file order

  std::size_t dropped() const { return tooFewCorners + badIndex + repeatedVertex; }
};

class CountingImporter final : public OpenMesh::IO::ImporterT<TriMesh> {
 public:
  explicit CountingImporter(TriMesh& mesh) : ImporterT(mesh), mesh_(mesh) {}

  using ImporterT::add_face;
  OpenMesh::FaceHandle add_face(const VHandles& corners) override {
    const std::size_t polygon = counts_.offered++;
    if (corners.size() < 3) {
      ++counts_.tooFewCorners;
      return OpenMesh::FaceHandle();
    }
    for (auto corner : corners) {
      if (!mesh_.is_valid_handle(corner)) {
        ++counts_.badIndex;
        return OpenMesh::FaceHandle();
      }
    }
    VHandles sorted = corners;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++counts_.repeatedVertex;
      return OpenMesh::FaceHandle();
    }
    if (corners.size() > 3) {
      ++counts_.triangulated;
      counts_.triangles += corners.size() - 2;
    }
    // One ImporterT call per fan triangle, so that ImporterT splits off exactly the triangles
    // that do not fit rather than the whole polygon.
    OpenMesh::FaceHandle last;
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      last = ImporterT::add_face(VHandles{corners[0], corners[i], corners[i + 1]});
      if (mesh_.status(last).fixed_nonmanifold() && counts_.nonManifold++ == 0)
        counts_.firstNonManifold = polygon;
    }
    return last;
  }

  const ImportCounts& counts() const { return counts_; }

 private:
  TriMesh& mesh_;
  ImportCounts counts_;
};

// ---------------------------------------------------------------------------------------------
// Text scanning

class LineReader {
 public:
  explicit LineReader(std::string_view text) : rest_(text) {}

  bool next(std::string_view& line) {
    if (rest_.empty()) return false;
    const auto end = rest_.find('\n');
    line = rest_.substr(0, end);
    rest_ = end == std::string_view::npos ? std::string_view() : rest_.substr(end + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++number_;
    return true;
  }
  // The next line with something other than blanks and a '#' comment, with the comment cut.
  bool nextData(std::string_view& line) {
    while (next(line)) {
      line = line.substr(0, line.find('#'));
      if (line.find_first_not_of(" \t") != std::string_view::npos) return true;
    }
    return false;
  }
  std::size_t number() const { return number_; }

 private:
  std::string_view rest_;
  std::size_t number_ = 0;
};

std::string_view nextToken(std::string_view& rest) {
  const auto begin = rest.find_first_not_of(" \t");
  if (begin == std::string_view::npos) {
    rest = {};
    return {};
  }
  rest.remove_prefix(begin);
  const auto end = std::min(rest.find_first_of(" \t"), rest.size());
  const auto token = rest.substr(0, end);
  rest.remove_prefix(end);
  return token;
}

// Accepts what strtod accepts (including nan and inf), so that such values are reported
// rather than misread.
std::optional<double> parseNumber(std::string_view token) {
  if (token.starts_with('+')) token.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size() || token.empty()) return std::nullopt;
  if (error == std::errc::result_out_of_range)
    return std::strtod(std::string(token).c_str(), nullptr);
  if (error != std::errc()) return std::nullopt;
  return value;
}

std::optional<std::size_t> parseCount(std::string_view token) {
  std::size_t value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size() || token.empty())
    return std::nullopt;
  return value;
}

// Three numbers from `rest`, or nothing if there are fewer.
std::optional<Vec3d> parsePoint(std::string_view rest) {
  Vec3d point(0, 0, 0);
  for (int i = 0; i < 3; ++i) {
    const auto value = parseNumber(nextToken(rest));
    if (!value) return std::nullopt;
    point[i] = *value;
  }
  return point;
}

// ---------------------------------------------------------------------------------------------
// OBJ

// The polygons of a file as written there, before OpenMesh sees them.
struct PolygonSoup {
  std::vector<Vec3d> points;
  std::vector<int> corners;       // 0-based vertex indices; -1 for an index that names none
  std::vector<std::size_t> ends;  // polygon i is corners[ends[i - 1], ends[i])
};

PolygonSoup parseObj(const fs::path& path, std::string_view text) {
  PolygonSoup soup;
  LineReader lines(text);
  std::string_view line;
  while (lines.nextData(line)) {
    std::string_view rest = line;
    const auto keyword = nextToken(rest);
    const auto where = [&] { return "line " + std::to_string(lines.number()) + ": "; };
    if (keyword == "v") {
      const auto point = parsePoint(rest);
      if (!point)
        throw fileError(path,
                        where() + "a vertex needs three numbers: '" + std::string(line) + "'");
      if (!isFinite(*point))
        throw nonFiniteError(path, "vertex", soup.points.size(), lines.number(),
                             "'" + std::string(line) + "'");
      soup.points.push_back(*point);
    } else if (keyword == "f") {
      for (auto token = nextToken(rest); !token.empty(); token = nextToken(rest)) {
        const auto digits = token.substr(0, token.find('/'));
        long long index = 0;
        const auto [end, error] =
            std::from_chars(digits.data(), digits.data() + digits.size(), index);
        if (error != std::errc() || end != digits.data() + digits.size() || digits.empty())
          throw fileError(path, where() + "'" + std::string(token) + "' is not a vertex index");
        // 1-based, or counted back from the last vertex so far when negative; 0 names none.
        index = index < 0 ? static_cast<long long>(soup.points.size()) + index : index - 1;
        soup.corners.push_back(index >= 0 && index <= INT_MAX ? static_cast<int>(index) : -1);
      }
      soup.ends.push_back(soup.corners.size());
    }
  }
  return soup;
}

void importSoup(const PolygonSoup& soup, CountingImporter& importer) {
  importer.reserve(static_cast<unsigned>(soup.points.size()),
                   static_cast<unsigned>(soup.corners.size()),
                   static_cast<unsigned>(soup.ends.size()));
  for (const auto& point : soup.points)
    importer.add_vertex(point);
  CountingImporter::VHandles corners;
  std::size_t begin = 0;
  for (std::size_t end : soup.ends) {
    corners.clear();
    for (std::size_t i = begin; i < end; ++i)
      corners.emplace_back(soup.corners[i]);
    importer.add_face(corners);
    begin = end;
  }
}

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

// ---------------------------------------------------------------------------------------------
// What PLY, OFF and STL files declare, read without OpenMesh: the counts, so that what OpenMesh's
// readers skip without a word can be counted, and the first non-finite coordinate, which its text
// readers cannot parse (they read "nan" as 0 or stop reading).

struct FileFacts {
  std::optional<std::size_t> vertices;
  std::optional<std::size_t> faces;
};

FileFacts probeOff(const fs::path& path, std::string_view text) {
  LineReader lines(text);
  std::string_view line;
  if (!lines.nextData(line)) return {};
  std::string_view rest = line;
  const auto keyword = nextToken(rest);
  // nOFF and 4OFF lay vertices out otherwise; binary OFF is checked after reading.
  if (!keyword.ends_with("OFF") || keyword.starts_with('n') || keyword.starts_with('4') ||
      line.find("BINARY") != std::string_view::npos)
    return {};
  if (rest.find_first_not_of(" \t") == std::string_view::npos) {
    if (!lines.nextData(line)) return {};
    rest = line;
  }
  const auto vertices = parseCount(nextToken(rest));
  const auto faces = parseCount(nextToken(rest));
  if (!vertices || !faces) return {};
  for (std::size_t i = 0; i < *vertices && lines.nextData(line); ++i) {
    const auto point = parsePoint(line);
    if (point && !isFinite(*point))
      throw nonFiniteError(path, "vertex", i, lines.number(), "'" + std::string(line) + "'");
  }
  return {vertices, faces};
}

FileFacts probePly(const fs::path& path, std::string_view text) {
  LineReader lines(text);
  std::string_view line;
  FileFacts facts;
  bool ascii = false;
  std::size_t elements = 0;
  bool vertexFirst = false;
  std::array<int, 3> xyz{-1, -1, -1};  // token positions of x, y, z in a vertex row
  int properties = 0;                  // of the current element
  bool listBeforeXyz = false;
  bool inVertex = false;
  while (lines.next(line)) {
    std::string_view rest = line;
    const auto keyword = nextToken(rest);
    if (keyword == "end_header") break;
    if (keyword == "format") {
      ascii = nextToken(rest) == "ascii";
    } else if (keyword == "element") {
      const auto name = nextToken(rest);
      const auto n = parseCount(nextToken(rest));
      inVertex = name == "vertex";
      properties = 0;
      if (inVertex) {
        facts.vertices = n;
        vertexFirst = elements == 0;
      } else if (name == "face") {
        facts.faces = n;
      }
      ++elements;
    } else if (keyword == "property" && inVertex) {
      const auto type = nextToken(rest);
      if (type == "list") {
        if (std::find(xyz.begin(), xyz.end(), -1) != xyz.end()) listBeforeXyz = true;
      } else {
        const auto name = nextToken(rest);
        const std::size_t axis = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : 3;
        if (axis < 3) xyz[axis] = properties;
      }
      ++properties;
    }
  }
  // Binary files are checked after reading; odd layouts are left to OpenMesh.
  if (!ascii || !vertexFirst || !facts.vertices || listBeforeXyz ||
      std::find(xyz.begin(), xyz.end(), -1) != xyz.end())
    return facts;
  const int last = *std::max_element(xyz.begin(), xyz.end());
  for (std::size_t i = 0; i < *facts.vertices && lines.nextData(line); ++i) {
    std::string_view rest = line;
    Vec3d point(0, 0, 0);
    bool complete = true;
    for (int k = 0; k <= last && complete; ++k) {
      const auto token = nextToken(rest);
      for (int axis = 0; axis < 3; ++axis) {
        if (xyz[axis] != k) continue;
        const auto value = parseNumber(token);
        complete = value.has_value();
        if (complete) point[axis] = *value;
      }
    }
    if (complete && !isFinite(point))
      throw nonFiniteError(path, "vertex", i, lines.number(), "'" + std::string(line) + "'");
  }
  return facts;
}

FileFacts probeStl(const fs::path& path, std::string_view text) {
  constexpr std::size_t kHeader = 84, kRecord = 50;
  // Binary when the size matches the triangle count in the header, as OpenMesh decides.
  if (text.size() >= kHeader) {
    std::uint32_t triangles = 0;
    std::memcpy(&triangles, text.data() + 80, sizeof triangles);
    if (text.size() == kHeader + kRecord * std::size_t(triangles)) {
      for (std::size_t t = 0; t < triangles; ++t) {
        std::array<float, 9> corners{};
        std::memcpy(corners.data(), text.data() + kHeader + kRecord * t + 12, sizeof corners);
        for (int c = 0; c < 3; ++c) {
          const Vec3d corner(corners[3 * c], corners[3 * c + 1], corners[3 * c + 2]);
          if (!isFinite(corner)) throw nonFiniteError(path, "facet", t, 0, formatPoint(corner));
        }
      }
      return {std::nullopt, triangles};
    }
  }
  LineReader lines(text);
  std::string_view line;
  std::size_t facets = 0;
  while (lines.nextData(line)) {
    std::string_view rest = line;
    const auto keyword = nextToken(rest);
    if (keyword == "facet") {
      ++facets;
    } else if (keyword == "vertex") {
      const auto point = parsePoint(rest);
      if (point && !isFinite(*point))
        throw nonFiniteError(path, "facet", facets - 1, lines.number(),
                             "'" + std::string(line) + "'");
    }
  }
  return {std::nullopt, facets};
}

// ---------------------------------------------------------------------------------------------

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, std::string("cannot be opened: ") + std::strerror(errno));
  std::string bytes;
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (!ec) bytes.resize(size);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (in.bad() || std::size_t(in.gcount()) != bytes.size())
    throw fileError(path, "cannot be read: " + std::string(std::strerror(errno)));
  return bytes;
}

// Why faces were dropped, e.g. "1 with a repeated vertex, 2 with a vertex index out of range".
std::string dropReasons(MeshFormat format, std::size_t skipped, const ImportCounts& counts) {
  std::string reasons;
  const auto add = [&](std::size_t n, std::string_view why) {
    if (n > 0) reasons += (reasons.empty() ? "" : ", ") + std::to_string(n) + std::string(why);
  };
  // OpenMesh's STL reader skips a facet when two corners merge into one vertex; the other
  // readers skip only what they cannot parse.
  add(skipped,
      format == MeshFormat::Stl ? " with corners at one position" : " that could not be read");
  add(counts.tooFewCorners, " with fewer than 3 corners");
  add(counts.repeatedVertex, " with a repeated vertex");
  add(counts.badIndex, " with a vertex index out of range");
  return reasons;
}

MeshReadResult checkImport(const fs::path& path, MeshFormat format, TriMesh surface,
                           const ImportCounts& counts, const FileFacts& facts,
                           const MeshReadOptions& options) {
  // Binary files can hold NaN and infinity, which the probes do not read.
  for (auto vertex : surface.vertices()) {
    if (!isFinite(surface.point(vertex)))
      throw nonFiniteError(path, "vertex", std::size_t(vertex.idx()), 0,
                           formatPoint(surface.point(vertex)));
  }

  const std::size_t inFile = std::max(facts.faces.value_or(0), counts.offered);
  if (inFile == 0) {
    throw fileError(
        path, surface.n_vertices() == 0
                  ? "holds no vertices and no faces"
                  : "has " + count(surface.n_vertices(), "vertex", "vertices") + " but no faces");
  }
  const std::size_t fileVertices = surface.n_vertices() - 3 * counts.nonManifold;
  if (facts.vertices && fileVertices < *facts.vertices) {
    throw fileError(path, "only " + std::to_string(fileVertices) + " of the " +
                              count(*facts.vertices, "vertex", "vertices") +
                              " it declares could be read");
  }

  MeshReadResult result;
  const std::size_t skipped = inFile - counts.offered;
  const std::size_t dropped = skipped + counts.dropped();
  if (dropped == inFile) {
    throw fileError(path, "none of its " + count(inFile, "face", "faces") +
                              " is usable: " + dropReasons(format, skipped, counts));
  }
  if (dropped > 0) {
    result.warnings.push_back(quoted(path) + ": dropped " + std::to_string(dropped) + " of " +
                              count(inFile, "face", "faces") + ": " +
                              dropReasons(format, skipped, counts));
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
    result.warnings.push_back(quoted(path) + ": repaired " + faces + " that" + problem +
                              ": split off onto their own copies of their vertices, " +
                              count(3 * counts.nonManifold, "vertex", "vertices") + " added");
  }

  if (counts.triangulated > 0) {
    result.warnings.push_back(
        quoted(path) + ": triangulated " + count(counts.triangulated, "polygon", "polygons") +
        " with more than 3 corners into " + count(counts.triangles, "triangle", "triangles") +
        " (fans from each first corner)");
  }

  result.mesh = std::make_shared<Mesh>(std::move(surface));
  return result;
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
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw fileError(path, "cannot be accessed: " + ec.message());
  if (!fs::exists(status)) throw fileError(path, "no such file");
  if (fs::is_directory(status)) throw fileError(path, "is a folder, not a mesh file");
  const auto format = meshFormatFromPath(path);
  if (!format) {
    throw fileError(path, "unknown mesh format '" + path.extension().string() +
                              "' (supported: .obj, .ply, .off, .stl)");
  }
  const std::string bytes = readBytes(path);

  TriMesh surface;
  CountingImporter importer(surface);
  FileFacts facts;
  if (*format == MeshFormat::Obj) {
    const PolygonSoup soup = parseObj(path, bytes);
    facts = {soup.points.size(), soup.ends.size()};
    OpenMeshSession session;
    importSoup(soup, importer);
  } else {
    facts = *format == MeshFormat::Ply   ? probePly(path, bytes)
            : *format == MeshFormat::Off ? probeOff(path, bytes)
                                         : probeStl(path, bytes);
    OpenMeshSession session;
    OpenMesh::IO::Options requested;  // points and faces only
    if (!OpenMesh::IO::IOManager().read(path.string(), importer, requested))
      throw fileError(path, "is not a readable " + std::string(toString(*format)) + " file");
  }
  return checkImport(path, *format, std::move(surface), importer.counts(), facts, options);
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
