// OFF (Geomview): a keyword ([ST][C][N]OFF, optionally "BINARY"), the counts "V F E", then V
// vertices and F faces ("n i_1 ... i_n", then an optional colour). Text files hold one vertex or
// face a line, with '#' comments; the first three numbers of a vertex are its position, the
// normal, colour and texture coordinates after them are skipped. Binary files hold big-endian
// 32-bit integers and floats. Coordinates are read as 32-bit floats, as Geomview stores them.
#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "geobrush/text.hpp"
#include "mesh_read.hpp"

namespace geobrush::meshread {
namespace {

struct OffKeyword {
  bool normals = false;
  bool colours = false;
  bool textureCoordinates = false;
};

// "OFF", "COFF", "NOFF", "CNOFF", "STOFF", ..., or nothing for a file without a keyword.
std::optional<OffKeyword> parseKeyword(const Source& source, std::string_view word,
                                       std::size_t line) {
  if (!word.ends_with("OFF")) return std::nullopt;
  std::string_view prefix = word.substr(0, word.size() - 3);
  OffKeyword keyword;
  if (prefix.starts_with("ST")) keyword.textureCoordinates = true, prefix.remove_prefix(2);
  if (prefix.starts_with("C")) keyword.colours = true, prefix.remove_prefix(1);
  if (prefix.starts_with("N")) keyword.normals = true, prefix.remove_prefix(1);
  if (prefix.starts_with("4") || prefix.starts_with("n"))
    throw source.error("line " + std::to_string(line) + ": " + quoteText(word) +
                       ": only 3D OFF files are read (not 4OFF or nOFF)");
  if (!prefix.empty())
    throw source.error("line " + std::to_string(line) + ": unknown OFF keyword " + quoteText(word));
  return keyword;
}

struct OffCounts {
  std::size_t vertices = 0;
  std::size_t faces = 0;
};

OffCounts parseCounts(const Source& source, std::string_view text, std::size_t line) {
  std::string_view rest = text;
  const auto vertices = parseInteger(nextToken(rest));
  const auto faces = parseInteger(nextToken(rest));
  if (!vertices || !faces || *vertices < 0 || *faces < 0)
    throw source.error("line " + std::to_string(line) +
                       ": expected the counts of vertices, faces and edges, got " +
                       quoteText(text));
  return {static_cast<std::size_t>(*vertices), static_cast<std::size_t>(*faces)};
}

// ---------------------------------------------------------------------------------------------
// Text

void readTextVertices(const Source& source, LineReader& lines, std::size_t n, PolygonSoup& soup) {
  std::string_view line;
  for (std::size_t i = 0; i < n; ++i) {
    lines.nextData(line);  // the lines were counted before
    std::string_view rest = line;
    Vec3d point;
    for (int k = 0; k < 3; ++k) {
      const auto value = parseNumber<float>(nextToken(rest));
      if (!value)
        throw source.error("line " + std::to_string(lines.number()) + ": vertex " +
                           std::to_string(i) + " needs three numbers: " + quoteText(line));
      point[k] = *value;
    }
    if (!isFinite(point)) throw source.nonFinite("vertex", i, lines.number(), quoteText(line));
    soup.points.push_back(point);
  }
}

void readTextFaces(const Source& source, LineReader& lines, std::size_t n, PolygonSoup& soup) {
  std::string_view line;
  for (std::size_t i = 0; i < n; ++i) {
    lines.nextData(line);
    std::string_view rest = line;
    const std::string where =
        "line " + std::to_string(lines.number()) + ": face " + std::to_string(i) + " (0-based) ";
    const auto corners = parseInteger(nextToken(rest));
    if (!corners || *corners < 0)
      throw source.error(where + "does not start with its number of corners: " + quoteText(line));
    // Each corner takes at least two characters of the line.
    if (static_cast<unsigned long long>(*corners) > rest.size() / 2)
      throw source.error(where + "declares " + std::to_string(*corners) +
                         " corners but its line is " + count(line.size(), "byte", "bytes") +
                         " long: " + quoteText(line));
    for (long long k = 0; k < *corners; ++k) {
      const auto token = nextToken(rest);
      const auto index = parseInteger(token);
      if (!index)
        throw source.error(where + "lists " + std::to_string(k) + " of its " +
                           std::to_string(*corners) + " corners: " + quoteText(line));
      soup.addCorner(*index);
    }
    soup.endPolygon();
  }
}

PolygonSoup readText(const Source& source, LineReader& lines, const OffCounts& counts) {
  // One line a vertex and a face: count them before trusting the counts.
  const std::size_t declared = counts.vertices + counts.faces;
  const std::size_t found = countDataLines(source.bytes, lines.position(), declared);
  if (found < declared)
    throw source.error("line " + std::to_string(lines.number()) + " declares " +
                       count(counts.vertices, "vertex", "vertices") + " and " +
                       count(counts.faces, "face", "faces") + ", but only " +
                       count(found, "line follows", "lines follow"));
  PolygonSoup soup;
  soup.points.reserve(counts.vertices);
  soup.ends.reserve(counts.faces);
  readTextVertices(source, lines, counts.vertices, soup);
  readTextFaces(source, lines, counts.faces, soup);
  return soup;
}

// ---------------------------------------------------------------------------------------------
// Binary

class BigEndianReader {
 public:
  BigEndianReader(const Source& source, std::size_t position)
      : source_(source), position_(position) {}

  std::size_t left() const { return source_.bytes.size() - position_; }
  std::size_t position() const { return position_; }

  template <typename T>
  T next(std::string_view what) {
    static_assert(sizeof(T) == 4);
    if (left() < 4)
      throw source_.error("ends inside " + std::string(what) + ", at byte " +
                          std::to_string(position_));
    std::array<unsigned char, 4> raw{};
    std::memcpy(raw.data(), source_.bytes.data() + position_, 4);
    position_ += 4;
    if constexpr (std::endian::native == std::endian::little) std::reverse(raw.begin(), raw.end());
    T value;
    std::memcpy(&value, raw.data(), 4);
    return value;
  }
  void skip(std::size_t values, std::string_view what) {
    if (left() / 4 < values)
      throw source_.error("ends inside " + std::string(what) + ", at byte " +
                          std::to_string(source_.bytes.size()));
    position_ += 4 * values;
  }

 private:
  const Source& source_;
  std::size_t position_;
};

PolygonSoup readBinary(const Source& source, const OffKeyword& keyword, std::size_t offset) {
  BigEndianReader in(source, offset);
  const std::int32_t vertices = in.next<std::int32_t>("the counts");
  const std::int32_t faces = in.next<std::int32_t>("the counts");
  in.next<std::int32_t>("the counts");
  const std::size_t floatsPerVertex =
      3 + 3 * keyword.normals + 4 * keyword.colours + 2 * keyword.textureCoordinates;
  // A vertex takes its floats, a face at least its corner count and its colour count.
  if (vertices < 0 || faces < 0 ||
      (std::size_t(vertices) * floatsPerVertex + 2 * std::size_t(faces)) > in.left() / 4)
    throw source.error("declares " + std::to_string(vertices) + " vertices and " +
                       std::to_string(faces) + " faces, which do not fit in the " +
                       count(in.left(), "byte", "bytes") + " after its counts");
  PolygonSoup soup;
  soup.points.reserve(std::size_t(vertices));
  for (std::int32_t i = 0; i < vertices; ++i) {
    Vec3d point;
    for (int k = 0; k < 3; ++k)
      point[k] = in.next<float>("a vertex");
    if (!isFinite(point)) throw source.nonFinite("vertex", std::size_t(i), 0, formatPoint(point));
    in.skip(floatsPerVertex - 3, "a vertex");
    soup.points.push_back(point);
  }
  for (std::int32_t i = 0; i < faces; ++i) {
    const std::int32_t corners = in.next<std::int32_t>("a face");
    if (corners < 0 || std::size_t(corners) > in.left() / 4)
      throw source.error("face " + std::to_string(i) + " (0-based) declares " +
                         std::to_string(corners) +
                         " corners, which do not fit in the rest of "
                         "the file (byte " +
                         std::to_string(in.position()) + ")");
    for (std::int32_t k = 0; k < corners; ++k)
      soup.addCorner(in.next<std::int32_t>("a face"));
    soup.endPolygon();
    const std::int32_t colours = in.next<std::int32_t>("a face");
    if (colours < 0 || colours > 4)
      throw source.error("face " + std::to_string(i) + " (0-based) declares " +
                         std::to_string(colours) + " colour components (at most 4)");
    in.skip(std::size_t(colours), "a face");
  }
  return soup;
}

}  // namespace

PolygonSoup readOff(const Source& source) {
  LineReader lines(source.bytes);
  std::string_view line;
  if (!lines.nextData(line)) throw source.error("holds no vertices and no faces");
  std::string_view rest = line;
  const auto first = nextToken(rest);
  const auto keyword = parseKeyword(source, first, lines.number());
  std::string_view afterKeyword = rest;
  if (keyword && nextToken(afterKeyword) == "BINARY") {
    // The binary part starts right after the keyword's line.
    return readBinary(source, *keyword, lines.position());
  }
  // The counts follow the keyword on its line or on the next; a file may also have no keyword.
  std::string_view counts = keyword ? rest : line;
  if (counts.find_first_not_of(" \t\r") == std::string_view::npos) {
    if (!lines.nextData(line))
      throw source.error("ends before the counts of vertices, faces and edges");
    counts = line;
  }
  return readText(source, lines, parseCounts(source, counts, lines.number()));
}

}  // namespace geobrush::meshread
