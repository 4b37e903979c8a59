// STL, binary (an 80-byte header, a 32-bit triangle count, 50 bytes a triangle) or ASCII
// ("solid", then "facet normal / outer loop / vertex x3 / endloop / endfacet", "endsolid").
// Coordinates are 32-bit floats in both; corners at equal positions become one vertex.
#include <array>
#include <bit>
#include <cstring>

#include "geobrush/text.hpp"
#include "mesh_read.hpp"

namespace geobrush::meshread {
namespace {

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kTriangleBytes = 50;

// Gives each distinct position one vertex index, in order of first use (-0 and 0 are one).
class CornerMerger {
 public:
  CornerMerger(PolygonSoup& soup, std::size_t expected) : soup_(soup), index_(expected) {}

  void add(std::array<float, 3> corner) {
    for (float& value : corner)
      if (value == 0) value = 0;  // -0 to +0
    std::uint64_t key = 0;
    for (float value : corner)
      key = key * 0x9e3779b97f4a7c15ull + std::bit_cast<std::uint32_t>(value);
    const auto same = [&](int v) {
      const Vec3d& p = soup_.points[std::size_t(v)];
      return float(p[0]) == corner[0] && float(p[1]) == corner[1] && float(p[2]) == corner[2];
    };
    const int v = index_.insert(key, int(soup_.points.size()), same);
    if (v == int(soup_.points.size())) soup_.points.emplace_back(corner[0], corner[1], corner[2]);
    soup_.corners.push_back(v);
  }

 private:
  PolygonSoup& soup_;
  KeyIndex index_;
};

// ---------------------------------------------------------------------------------------------
// Binary

std::uint32_t littleEndian32(const char* bytes) {
  std::array<unsigned char, 4> raw{};
  std::memcpy(raw.data(), bytes, raw.size());
  return std::uint32_t(raw[0]) | std::uint32_t(raw[1]) << 8 | std::uint32_t(raw[2]) << 16 |
         std::uint32_t(raw[3]) << 24;
}

std::uint32_t declaredTriangles(std::string_view bytes) {
  return littleEndian32(bytes.data() + 80);
}

float littleEndianFloat(const char* bytes) {
  return std::bit_cast<float>(littleEndian32(bytes));
}

PolygonSoup readBinary(const Source& source) {
  const std::size_t triangles = declaredTriangles(source.bytes);
  PolygonSoup soup;
  soup.ends.reserve(triangles);
  soup.corners.reserve(3 * triangles);
  CornerMerger merger(soup, 3 * triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const char* record = source.bytes.data() + kHeaderBytes + kTriangleBytes * t;
    std::array<std::array<float, 3>, 3> corners{};
    for (std::size_t c = 0; c < 3; ++c) {
      for (std::size_t k = 0; k < 3; ++k)
        corners[c][k] = littleEndianFloat(record + 12 + 12 * c + 4 * k);
      const Vec3d corner(corners[c][0], corners[c][1], corners[c][2]);
      if (!isFinite(corner)) throw source.nonFinite("facet", t, 0, formatPoint(corner));
    }
    for (const auto& corner : corners)
      merger.add(corner);
    soup.endPolygon();
  }
  return soup;
}

// ---------------------------------------------------------------------------------------------
// ASCII

class AsciiStl {
 public:
  AsciiStl(const Source& source, PolygonSoup& soup)
      : source_(source), lines_(source.bytes), soup_(soup), merger_(soup, 0) {}

  void read() {
    bool inSolid = false;
    std::string_view line;
    while (lines_.nextData(line)) {
      std::string_view rest = line;
      const auto keyword = nextToken(rest);
      if (keyword == "solid" && !inSolid) {
        inSolid = true;
      } else if (keyword == "endsolid" && inSolid) {
        inSolid = false;
      } else if (keyword == "facet" && inSolid) {
        readFacet();
      } else {
        throw unexpected(line, inSolid ? "'facet' or 'endsolid'" : "'solid'");
      }
    }
    if (inSolid) {
      soup_.warnings.push_back(quotePath(source_.path) + ": ends after " +
                               count(facets_, "facet", "facets") +
                               " without 'endsolid': the file may be cut short");
    }
  }

 private:
  // "outer loop", three "vertex x y z", "endloop", "endfacet".
  void readFacet() {
    expect("outer");
    std::array<std::array<float, 3>, 3> corners{};
    for (auto& corner : corners)
      corner = readVertex();
    expect("endloop");
    expect("endfacet");
    for (const auto& corner : corners)
      merger_.add(corner);
    soup_.endPolygon();
    ++facets_;
  }

  std::array<float, 3> readVertex() {
    std::string_view rest = expect("vertex");
    std::array<float, 3> corner{};
    for (float& value : corner) {
      const auto number = parseNumber<float>(nextToken(rest));
      if (!number)
        throw source_.error("line " + std::to_string(lines_.number()) +
                            ": a vertex needs three numbers: " + quoteText(current_));
      value = *number;
    }
    if (!isFinite(Vec3d(corner[0], corner[1], corner[2])))
      throw source_.nonFinite("facet", facets_, lines_.number(), quoteText(current_));
    return corner;
  }

  // The rest of the next line, which must start with `keyword`.
  std::string_view expect(std::string_view keyword) {
    if (!lines_.nextData(current_)) {
      throw source_.error("ends inside facet " + std::to_string(facets_) + " (0-based), at line " +
                          std::to_string(lines_.number()) + " (byte " +
                          std::to_string(source_.bytes.size()) + "): the file is cut short");
    }
    std::string_view rest = current_;
    if (nextToken(rest) != keyword) throw unexpected(current_, "'" + std::string(keyword) + "'");
    return rest;
  }

  MeshError unexpected(std::string_view line, const std::string& expected) const {
    return source_.error("line " + std::to_string(lines_.number()) + ": expected " + expected +
                         ", got " + quoteText(line));
  }

  const Source& source_;
  LineReader lines_;
  PolygonSoup& soup_;
  CornerMerger merger_;
  std::string_view current_;
  std::size_t facets_ = 0;
};

// ASCII files start with "solid" and hold no NUL byte; binary ones almost always hold NULs (in
// the count's high byte, in zero coordinates, in the attribute bytes), even when a careless
// writer starts their header with "solid".
bool looksAscii(std::string_view bytes) {
  std::string_view rest = bytes;
  return nextToken(rest) == "solid" && bytes.find('\0') == std::string_view::npos;
}

}  // namespace

PolygonSoup readStl(const Source& source) {
  const std::string_view bytes = source.bytes;
  const bool sizeFitsCount =
      bytes.size() >= kHeaderBytes &&
      bytes.size() - kHeaderBytes == kTriangleBytes * std::size_t(declaredTriangles(bytes));
  if (sizeFitsCount) return readBinary(source);
  if (looksAscii(bytes)) {
    PolygonSoup soup;
    AsciiStl(source, soup).read();
    return soup;
  }
  if (bytes.size() < kHeaderBytes)
    throw source.error("is neither ASCII STL (it does not start with 'solid') nor binary STL (" +
                       count(bytes.size(), "byte", "bytes") + ", less than the 84-byte header)");
  const std::size_t triangles = declaredTriangles(bytes);
  const std::size_t expected = kHeaderBytes + kTriangleBytes * triangles;
  throw source.error("binary STL declares " + count(triangles, "triangle", "triangles") +
                     ", which take 84 + 50 x " + std::to_string(triangles) + " = " +
                     std::to_string(expected) + " bytes, but the file has " +
                     std::to_string(bytes.size()) +
                     (bytes.size() < expected ? ": it is cut short" : ""));
}

}  // namespace geobrush::meshread
