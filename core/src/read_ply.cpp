// PLY (Turk 1994), ASCII and binary of either byte order: the "vertex" element's x, y, z and the
// "face" element's vertex_indices (or vertex_index) list; other elements and properties are
// skipped. Coordinates keep their declared type: a float property is read as a 32-bit float.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "geobrush/text.hpp"
#include "mesh_read.hpp"

namespace geobrush::meshread {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

std::optional<PlyType> plyType(std::string_view name) {
  static const std::array<std::pair<std::string_view, PlyType>, 16> kNames{{
      {"char", PlyType::Int8},
      {"int8", PlyType::Int8},
      {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},
      {"short", PlyType::Int16},
      {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},
      {"uint16", PlyType::UInt16},
      {"int", PlyType::Int32},
      {"int32", PlyType::Int32},
      {"uint", PlyType::UInt32},
      {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},
      {"float32", PlyType::Float32},
      {"double", PlyType::Float64},
      {"float64", PlyType::Float64},
  }};
  for (const auto& [text, type] : kNames)
    if (text == name) return type;
  return std::nullopt;
}

std::size_t sizeOf(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 8;
}

bool isInteger(PlyType type) {
  return type != PlyType::Float32 && type != PlyType::Float64;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;   // of the value, or of a list's entries
  std::optional<PlyType> listCount;  // the type of a list's length
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::size_t line = 0;  // of its "element" line
  std::vector<PlyProperty> properties;

  // The least room one item takes: a list may be empty. In ASCII each value takes a character
  // and a separator.
  std::size_t leastBytes(PlyFormat format) const {
    std::size_t bytes = 0;
    for (const auto& property : properties)
      bytes += format == PlyFormat::Ascii ? 2 : sizeOf(property.listCount.value_or(property.type));
    return bytes;
  }
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t bodyOffset = 0;  // the byte after "end_header"'s line
  std::size_t bodyLine = 0;    // the line "end_header" is on
};

// ---------------------------------------------------------------------------------------------
// Header

void readFormatLine(const Source& source, std::string_view rest, std::size_t line,
                    PlyHeader& header) {
  const auto name = nextToken(rest);
  if (name == "ascii") {
    header.format = PlyFormat::Ascii;
  } else if (name == "binary_little_endian") {
    header.format = PlyFormat::BinaryLittleEndian;
  } else if (name == "binary_big_endian") {
    header.format = PlyFormat::BinaryBigEndian;
  } else {
    throw source.error("line " + std::to_string(line) + ": unknown PLY format " + quoteText(name) +
                       " (ascii, binary_little_endian or binary_big_endian)");
  }
}

void readElementLine(const Source& source, std::string_view rest, std::size_t line,
                     PlyHeader& header) {
  PlyElement element;
  element.name = nextToken(rest);
  const auto countText = nextToken(rest);
  const auto count = parseInteger(countText);
  if (element.name.empty() || !count || *count < 0)
    throw source.error("line " + std::to_string(line) +
                       ": an element needs a name and a count, got " +
                       quoteText(element.name + " " + std::string(countText)));
  element.count = static_cast<std::size_t>(*count);
  element.line = line;
  header.elements.push_back(std::move(element));
}

void readPropertyLine(const Source& source, std::string_view rest, std::size_t line,
                      PlyHeader& header) {
  const std::string where = "line " + std::to_string(line) + ": ";
  if (header.elements.empty()) throw source.error(where + "a property before any element");
  PlyProperty property;
  auto typeName = nextToken(rest);
  if (typeName == "list") {
    const auto countName = nextToken(rest);
    property.listCount = plyType(countName);
    if (!property.listCount || !isInteger(*property.listCount))
      throw source.error(where + "a list's length needs an integer type, got " +
                         quoteText(countName));
    typeName = nextToken(rest);
  }
  const auto type = plyType(typeName);
  if (!type) throw source.error(where + "unknown property type " + quoteText(typeName));
  property.type = *type;
  property.name = nextToken(rest);
  if (property.name.empty()) throw source.error(where + "a property needs a name");
  header.elements.back().properties.push_back(std::move(property));
}

PlyHeader readHeader(const Source& source) {
  LineReader lines(source.bytes);
  std::string_view line;
  if (!lines.next(line) || line != "ply")
    throw source.error("is not a PLY file: it does not start with the line 'ply'");
  PlyHeader header;
  bool hasFormat = false;
  while (lines.next(line)) {
    std::string_view rest = line;
    const auto keyword = nextToken(rest);
    if (keyword == "end_header") {
      if (!hasFormat) throw source.error("the PLY header has no 'format' line");
      header.bodyOffset = lines.position();
      header.bodyLine = lines.number();
      return header;
    }
    if (keyword == "format") {
      readFormatLine(source, rest, lines.number(), header);
      hasFormat = true;
    } else if (keyword == "element") {
      readElementLine(source, rest, lines.number(), header);
    } else if (keyword == "property") {
      readPropertyLine(source, rest, lines.number(), header);
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      throw source.error("line " + std::to_string(lines.number()) + ": unknown PLY header line " +
                         quoteText(line));
    }
  }
  throw source.error("the PLY header has no 'end_header' line");
}

// Every element's items fit in what follows the header, at the least room each can take.
void checkDeclaredSizes(const Source& source, const PlyHeader& header) {
  std::size_t left = source.bytes.size() - header.bodyOffset;
  // The last ASCII value needs no separator after it.
  if (header.format == PlyFormat::Ascii) ++left;
  for (const auto& element : header.elements) {
    const std::size_t least = element.leastBytes(header.format);
    if (least == 0) continue;
    if (element.count > left / least) {
      throw source.error(
          "line " + std::to_string(element.line) + " declares " + std::to_string(element.count) +
          " " + quoteText(element.name) + " elements of at least " + count(least, "byte", "bytes") +
          " each, but only " + count(source.bytes.size() - header.bodyOffset, "byte", "bytes") +
          " follow the header");
    }
    left -= element.count * least;
  }
}

// ---------------------------------------------------------------------------------------------
// Body

// The item being read, for messages: where it starts.
struct Place {
  const PlyElement* element;
  std::size_t item;
  std::size_t line;  // ASCII
  std::size_t byte;  // binary
};

// Reads values in the file's encoding.
class ValueReader {
 public:
  ValueReader(const Source& source, const PlyHeader& header)
      : source_(source),
        format_(header.format),
        position_(header.bodyOffset),
        line_(header.bodyLine + 1) {}

  double number(PlyType type, const Place& place) {
    if (format_ == PlyFormat::Ascii) return asciiNumber(type, place);
    const std::size_t size = sizeOf(type);
    if (source_.bytes.size() - position_ < size) throw ended(place);
    std::array<unsigned char, 8> raw{};
    std::memcpy(raw.data(), source_.bytes.data() + position_, size);
    position_ += size;
    const bool swap =
        (format_ == PlyFormat::BinaryBigEndian) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(size));
    return decode(type, raw.data());
  }

  // Skips `n` values of `type` in binary files; reads them in ASCII, where sizes vary.
  void skip(PlyType type, std::size_t n, const Place& place) {
    if (format_ == PlyFormat::Ascii) {
      for (std::size_t i = 0; i < n; ++i)
        asciiNumber(type, place);
      return;
    }
    if ((source_.bytes.size() - position_) / sizeOf(type) < n) throw ended(place);
    position_ += n * sizeOf(type);
  }

  Place placeOf(const PlyElement& element, std::size_t item) {
    if (format_ == PlyFormat::Ascii) skipBlanks();
    return {&element, item, line_, position_};
  }
  // The number of values a list of `count` entries of `type` could hold at most here.
  std::size_t room(PlyType type) const {
    const std::size_t left = source_.bytes.size() - position_;
    return format_ == PlyFormat::Ascii ? left / 2 + 1 : left / sizeOf(type);
  }

  MeshError error(const Place& place, const std::string& cause) const {
    return source_.error(where(place) + ": " + cause);
  }

 private:
  static double decode(PlyType type, const unsigned char* raw) {
    const auto as = [raw]<typename T>(T) {
      T value;
      std::memcpy(&value, raw, sizeof value);
      return static_cast<double>(value);
    };
    switch (type) {
      case PlyType::Int8:
        return as(std::int8_t());
      case PlyType::UInt8:
        return as(std::uint8_t());
      case PlyType::Int16:
        return as(std::int16_t());
      case PlyType::UInt16:
        return as(std::uint16_t());
      case PlyType::Int32:
        return as(std::int32_t());
      case PlyType::UInt32:
        return as(std::uint32_t());
      case PlyType::Float32:
        return as(float());
      case PlyType::Float64:
        return as(double());
    }
    return 0;
  }

  double asciiNumber(PlyType type, const Place& place) {
    const std::string_view token = nextAsciiToken();
    if (token.empty()) throw ended(place);
    if (isInteger(type)) {
      const auto value = parseInteger(token);
      if (!value) throw error(place, quoteText(token) + " is not an integer");
      return static_cast<double>(*value);
    }
    if (type == PlyType::Float32) {
      const auto value = parseNumber<float>(token);
      if (!value) throw error(place, quoteText(token) + " is not a number");
      return *value;
    }
    const auto value = parseNumber<double>(token);
    if (!value) throw error(place, quoteText(token) + " is not a number");
    return *value;
  }

  static bool blank(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

  void skipBlanks() {
    const std::string_view bytes = source_.bytes;
    for (; position_ < bytes.size() && blank(bytes[position_]); ++position_)
      line_ += bytes[position_] == '\n';
  }

  std::string_view nextAsciiToken() {
    skipBlanks();
    const std::size_t begin = position_;
    while (position_ < source_.bytes.size() && !blank(source_.bytes[position_]))
      ++position_;
    return source_.bytes.substr(begin, position_ - begin);
  }

  std::string where(const Place& place) const {
    std::string text = place.element->name + " " + std::to_string(place.item) + " (0-based, ";
    if (format_ == PlyFormat::Ascii) return text + "line " + std::to_string(place.line) + ")";
    return text + "byte " + std::to_string(place.byte) + ")";
  }

  MeshError ended(const Place& place) const {
    return source_.error("ends inside " + quoteText(place.element->name) + " " +
                         std::to_string(place.item) + " (0-based) of the " +
                         std::to_string(place.element->count) + " it declares, at " +
                         (format_ == PlyFormat::Ascii ? "line " + std::to_string(line_)
                                                      : "byte " + std::to_string(position_)));
  }

  const Source& source_;
  PlyFormat format_;
  std::size_t position_;
  std::size_t line_;
};

// What the reader keeps of an element's properties.
enum class Role { Skip, X, Y, Z, Corners };

// The vertex element's first x, y and z, and the face element's first vertex_indices (or
// vertex_index) list.
std::vector<Role> rolesOf(const Source& source, const PlyElement& element) {
  std::vector<Role> roles(element.properties.size(), Role::Skip);
  const bool vertex = element.name == "vertex";
  const bool face = element.name == "face";
  const auto take = [&](std::size_t i, Role role) {
    if (std::find(roles.begin(), roles.end(), role) == roles.end()) roles[i] = role;
  };
  for (std::size_t i = 0; i < roles.size(); ++i) {
    const PlyProperty& property = element.properties[i];
    const bool list = property.listCount.has_value();
    if (vertex && !list && property.name == "x") take(i, Role::X);
    if (vertex && !list && property.name == "y") take(i, Role::Y);
    if (vertex && !list && property.name == "z") take(i, Role::Z);
    if (face && list && (property.name == "vertex_indices" || property.name == "vertex_index"))
      take(i, Role::Corners);
  }
  if (vertex) {
    for (Role axis : {Role::X, Role::Y, Role::Z})
      if (std::find(roles.begin(), roles.end(), axis) == roles.end())
        throw source.error("line " + std::to_string(element.line) +
                           ": the vertex element has no x, y and z properties");
  }
  if (face && std::find(roles.begin(), roles.end(), Role::Corners) == roles.end())
    throw source.error("line " + std::to_string(element.line) +
                       ": the face element has no vertex_indices list");
  return roles;
}

// A vertex index from a value of any type; one that names no vertex becomes -1.
long long toIndex(double value) {
  constexpr double kLargest = 9.0e18;
  return value == std::floor(value) && std::abs(value) < kLargest ? static_cast<long long>(value)
                                                                  : -1;
}

void readItem(const PlyElement& element, const std::vector<Role>& roles, Place place,
              ValueReader& values, PolygonSoup& soup) {
  Vec3d point(0, 0, 0);
  for (std::size_t i = 0; i < roles.size(); ++i) {
    const PlyProperty& property = element.properties[i];
    if (!property.listCount) {
      const double value = values.number(property.type, place);
      if (roles[i] == Role::X || roles[i] == Role::Y || roles[i] == Role::Z)
        point[static_cast<int>(roles[i]) - static_cast<int>(Role::X)] = value;
      continue;
    }
    const double length = values.number(*property.listCount, place);
    if (length < 0 || length > double(values.room(property.type)))
      throw values.error(place, "a list of " + std::to_string(static_cast<long long>(length)) +
                                    " entries does not fit in the rest of the file");
    const auto entries = static_cast<std::size_t>(length);
    if (roles[i] != Role::Corners) {
      values.skip(property.type, entries, place);
      continue;
    }
    for (std::size_t k = 0; k < entries; ++k)
      soup.addCorner(toIndex(values.number(property.type, place)));
    soup.endPolygon();
  }
  if (element.name == "vertex") soup.points.push_back(point);
}

}  // namespace

PolygonSoup readPly(const Source& source) {
  const PlyHeader header = readHeader(source);
  checkDeclaredSizes(source, header);
  PolygonSoup soup;
  ValueReader values(source, header);
  const std::size_t bodyBytes = source.bytes.size() - header.bodyOffset;
  for (const auto& element : header.elements) {
    if (element.properties.empty()) continue;
    const std::vector<Role> roles = rolesOf(source, element);
    if (element.name == "vertex") reserveAtMost(soup.points, element.count, bodyBytes, 3);
    if (element.name == "face") reserveAtMost(soup.ends, element.count, bodyBytes, 4);
    for (std::size_t item = 0; item < element.count; ++item) {
      const Place place = values.placeOf(element, item);
      readItem(element, roles, place, values, soup);
      if (element.name == "vertex" && !isFinite(soup.points.back())) {
        const std::size_t line = header.format == PlyFormat::Ascii ? place.line : 0;
        throw source.nonFinite("vertex", item, line, formatPoint(soup.points.back()));
      }
    }
  }
  return soup;
}

}  // namespace geobrush::meshread
