// Node parameters: declared kinds, values, and their text forms.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace geobrush {

using Vec3 = std::array<double, 3>;

// What a parameter holds. Paths are strings that the framework resolves:
// input paths against the graph file's folder (and their file's size and
// modification time enter the cache key), output paths against the output
// folder (`geobrush run --out DIR`, else the graph file's folder).
enum class ParamKind { Bool, Int, Double, String, Enum, InputPath, OutputPath, Vec3, DoubleList };

std::string_view toString(ParamKind kind);

using ParamValue = std::variant<bool, std::int64_t, double, std::string, Vec3, std::vector<double>>;
using ParamMap = std::map<std::string, ParamValue>;

struct ParamDecl {
  std::string name;
  ParamKind kind = ParamKind::Double;
  ParamValue defaultValue;
  std::string doc;
  std::optional<double> min;  // inclusive bounds for Int, Double and each Vec3/list entry
  std::optional<double> max;
  std::vector<std::string> choices;  // Enum only
  // DoubleList only: values come in rows of this many (e.g. 4 for x, y, z, radius).
  int rowSize = 1;
};

// Checks `value` against the declaration; returns an error text or nothing.
// Ints are accepted where doubles are declared (and converted by coerceParam).
std::optional<std::string> checkParam(const ParamDecl& decl, const ParamValue& value);
// Converts a loosely typed value (as read from JSON or the command line) to
// the declared kind; throws std::invalid_argument with the reason.
ParamValue coerceParam(const ParamDecl& decl, const ParamValue& value);
// Parses the command-line text form: "true", "3", "0.5", "a,b,c".
ParamValue parseParamText(const ParamDecl& decl, const std::string& text);
// A short human form for messages and tables.
std::string formatParam(const ParamValue& value);

}  // namespace geobrush
