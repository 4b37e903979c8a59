// The mesh file readers (read_obj.cpp, read_ply.cpp, read_off.cpp, read_stl.cpp): each turns a
// file's bytes into the polygons it lists, and the scanning they share.
//
// The rule every reader keeps: a size the file declares (a count of vertices, faces or list
// entries) is checked against the bytes the file still holds before anything is allocated or
// looped over for it; every loop consumes bytes, so a reader ends within a time linear in the
// file's size; and every failure is a MeshError naming the file and the place (line or byte).
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "geobrush/mesh_io.hpp"

namespace geobrush::meshread {

using OpenMesh::Vec3d;

// The polygons of a file as written there, before OpenMesh sees them.
struct PolygonSoup {
  std::vector<Vec3d> points;
  std::vector<int> corners;       // 0-based vertex indices; -1 for an index that names none
  std::vector<std::size_t> ends;  // polygon i is corners[ends[i - 1], ends[i])
  std::vector<std::string> warnings;

  void addCorner(long long index);  // an index out of int's range names no vertex
  void endPolygon() { ends.push_back(corners.size()); }
};

// The file being read: its name for messages and its bytes.
struct Source {
  const std::filesystem::path& path;
  std::string_view bytes;

  MeshError error(const std::string& cause) const;
  // "vertex 3 (0-based, line 7) has a non-finite coordinate: DETAIL"; line 0 for none.
  MeshError nonFinite(std::string_view element, std::size_t index, std::size_t line,
                      const std::string& detail) const;
};

PolygonSoup readObj(const Source& source);
PolygonSoup readPly(const Source& source);
PolygonSoup readOff(const Source& source);
// Corners at equal positions become one vertex, in order of first use: STL lists each
// triangle's corners, not shared vertices.
PolygonSoup readStl(const Source& source);

// What happened to the file's polygons on their way into the mesh.
struct ImportCounts {
  std::size_t offered = 0;  // polygons in the file
  std::size_t tooFewCorners = 0;
  std::size_t badIndex = 0;
  std::size_t repeatedVertex = 0;
  std::size_t triangulated = 0;      // polygons with more than 3 corners
  std::size_t triangles = 0;         // made from those polygons
  std::size_t nonManifold = 0;       // triangles split off onto copies of their vertices
  std::size_t firstNonManifold = 0;  // polygon index in file order

  std::size_t dropped() const { return tooFewCorners + badIndex + repeatedVertex; }
};

// Builds `out` (empty) from the soup in time linear in its size (mesh_link.cpp): polygons with
// fewer than 3 corners, a repeated vertex or an index out of range are dropped, the others
// fan-triangulated; triangles that cannot join the others as a manifold are split off onto copies
// of their corners, marked fixed_nonmanifold.
ImportCounts linkSoup(const PolygonSoup& soup, TriMesh& out);

// ---------------------------------------------------------------------------------------------
// Scanning

bool isFinite(const Vec3d& p);
// "(x, y, z)" with each coordinate in its shortest form.
std::string formatPoint(const Vec3d& p);
// "3 vertices", "1 face".
std::string count(std::size_t n, std::string_view one, std::string_view many);

// Lines of a text, with their 1-based numbers and byte offsets.
class LineReader {
 public:
  explicit LineReader(std::string_view text, std::size_t offset = 0)
      : text_(text), position_(offset) {}

  bool next(std::string_view& line);
  // The next line with something other than blanks and a '#' comment, with the comment cut.
  bool nextData(std::string_view& line);
  std::size_t number() const { return number_; }  // of the line last returned
  std::size_t lineStart() const { return lineStart_; }
  std::size_t position() const { return position_; }  // byte after the line last returned

 private:
  std::string_view text_;
  std::size_t position_;
  std::size_t lineStart_ = 0;
  std::size_t number_ = 0;
};

// Counts lines with data (as LineReader::nextData finds them) from `offset`, stopping at `enough`.
std::size_t countDataLines(std::string_view text, std::size_t offset, std::size_t enough);

// The next blank-separated token of `rest` (blanks: space, tab, CR, LF, VT, FF), removed from
// it; empty at the end.
std::string_view nextToken(std::string_view& rest);

// A decimal number as strtod reads it (with nan and inf, so that such values are reported rather
// than misread), rounded once to T.
template <typename T>
std::optional<T> parseNumber(std::string_view token);
extern template std::optional<double> parseNumber<double>(std::string_view);
extern template std::optional<float> parseNumber<float>(std::string_view);

// A decimal integer (optionally signed), or nothing.
std::optional<long long> parseInteger(std::string_view token);

// Three numbers from `rest`, or nothing if there are fewer.
std::optional<Vec3d> parsePoint(std::string_view rest);

// Ints found by a 64-bit key: open addressing with linear probing, several times faster than
// std::unordered_map on the millions of lookups a large mesh takes. A key may stand for more than
// one item (a hash): `same(value)` then tells whether the stored value is the item looked for.
class KeyIndex {
 public:
  explicit KeyIndex(std::size_t expected);

  // The value stored for the item, or -1.
  template <typename Same>
  int find(std::uint64_t key, Same same) const {
    for (std::size_t i = slot(key);; i = (i + 1) & (keys_.size() - 1)) {
      if (values_[i] < 0) return -1;
      if (keys_[i] == key && same(values_[i])) return values_[i];
    }
  }
  // Stores `value` (>= 0) for the item unless one is stored; returns the value stored for it.
  template <typename Same>
  int insert(std::uint64_t key, int value, Same same) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    std::size_t i = slot(key);
    for (; values_[i] >= 0; i = (i + 1) & (keys_.size() - 1))
      if (keys_[i] == key && same(values_[i])) return values_[i];
    keys_[i] = key;
    values_[i] = value;
    ++size_;
    return value;
  }

 private:
  std::size_t slot(std::uint64_t key) const;
  void grow();

  std::vector<std::uint64_t> keys_;
  std::vector<int> values_;  // -1 where free
  std::size_t size_ = 0;
};

// Reserves room for `declared` items, but never more than `bytesLeft` bytes of the file could
// hold at `bytesPerItem` each: what a file declares is not what it holds.
template <typename T>
void reserveAtMost(std::vector<T>& items, std::size_t declared, std::size_t bytesLeft,
                   std::size_t bytesPerItem) {
  items.reserve(items.size() +
                std::min(declared, bytesLeft / std::max<std::size_t>(1, bytesPerItem)));
}

}  // namespace geobrush::meshread
