#include "geobrush/param.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "geobrush/text.hpp"

namespace geobrush {
namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  // Shortest form that reads back to the same double.
  for (int precision = 1; precision < 17; ++precision) {
    char shorter[32];
    std::snprintf(shorter, sizeof shorter, "%.*g", precision, value);
    if (std::strtod(shorter, nullptr) == value) {
      std::snprintf(text, sizeof text, "%s", shorter);
      break;
    }
  }
  // %g writes 400 as 4e+02 at one digit: a whole number is written whole where that is shorter.
  if (std::strchr(text, 'e') && std::trunc(value) == value && std::abs(value) < 1e16) {
    char whole[32];
    std::snprintf(whole, sizeof whole, "%.0f", value);
    if (std::strlen(whole) <= std::strlen(text)) return whole;
  }
  return text;
}

const char* kindOfValue(const ParamValue& value) {
  switch (value.index()) {
    case 0:
      return "a boolean";
    case 1:
      return "an integer";
    case 2:
      return "a number";
    case 3:
      return "a string";
    case 4:
      return "a 3-vector";
    default:
      return "a list of numbers";
  }
}

std::optional<std::string> checkRange(const ParamDecl& decl, double value) {
  if (!std::isfinite(value)) return "must be a finite number";
  if ((decl.min && value < *decl.min) || (decl.max && value > *decl.max)) {
    return number(value) + " is outside [" + (decl.min ? number(*decl.min) : "-inf") + ", " +
           (decl.max ? number(*decl.max) : "inf") + "]";
  }
  return std::nullopt;
}

double parseDouble(const std::string& text) {
  double value = 0;
  const char* begin = text.data();
  const char* end = begin + text.size();
  while (begin < end && *begin == ' ')
    ++begin;
  if (begin < end && *begin == '+') ++begin;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range && ptr == end)
    throw std::invalid_argument("number out of range: " + quoteText(text));
  if (ec != std::errc() || ptr != end)
    throw std::invalid_argument(quoteText(text) + " is not a number");
  return value;
}

std::vector<double> parseNumberList(const std::string& text) {
  std::vector<double> values;
  if (text.empty()) return values;
  std::size_t start = 0;
  while (true) {
    std::size_t comma = text.find(',', start);
    values.push_back(parseDouble(text.substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return values;
}

}  // namespace

std::string_view toString(ParamKind kind) {
  switch (kind) {
    case ParamKind::Bool:
      return "bool";
    case ParamKind::Int:
      return "int";
    case ParamKind::Double:
      return "double";
    case ParamKind::String:
      return "string";
    case ParamKind::Enum:
      return "enum";
    case ParamKind::InputPath:
      return "input_path";
    case ParamKind::OutputPath:
      return "output_path";
    case ParamKind::Vec3:
      return "vec3";
    case ParamKind::DoubleList:
      return "double_list";
  }
  return "unknown";
}

std::optional<std::string> checkParam(const ParamDecl& decl, const ParamValue& value) {
  switch (decl.kind) {
    case ParamKind::Bool:
      if (!std::holds_alternative<bool>(value)) return "expected a boolean";
      return std::nullopt;
    case ParamKind::Int:
      if (!std::holds_alternative<std::int64_t>(value)) return "expected an integer";
      return checkRange(decl, double(std::get<std::int64_t>(value)));
    case ParamKind::Double:
      if (auto* i = std::get_if<std::int64_t>(&value)) return checkRange(decl, double(*i));
      if (!std::holds_alternative<double>(value)) return "expected a number";
      return checkRange(decl, std::get<double>(value));
    case ParamKind::String: {
      auto* text = std::get_if<std::string>(&value);
      if (!text) return "expected a string";
      if (!isUtf8(*text)) return quoteText(*text) + " is not UTF-8 text, as graph files hold";
      return std::nullopt;
    }
    case ParamKind::InputPath:
    case ParamKind::OutputPath: {
      auto* text = std::get_if<std::string>(&value);
      if (!text) return "expected a string";
      if (!isUtf8(*text)) return quoteText(*text) + " is not UTF-8 text, as graph files hold";
      // The file system would see the path only up to the NUL: another file than the one named.
      if (text->find('\0') != std::string::npos)
        return quoteText(*text) + ": a path may not contain a NUL character";
      return std::nullopt;
    }
    case ParamKind::Enum: {
      auto* text = std::get_if<std::string>(&value);
      if (!text) return "expected a string";
      if (std::find(decl.choices.begin(), decl.choices.end(), *text) == decl.choices.end()) {
        std::string list;
        for (const auto& choice : decl.choices)
          list += (list.empty() ? "" : ", ") + choice;
        return quoteText(*text) + " is not one of: " + list;
      }
      return std::nullopt;
    }
    case ParamKind::Vec3: {
      auto* v = std::get_if<Vec3>(&value);
      if (!v) return "expected a 3-vector [x, y, z]";
      for (double x : *v)
        if (auto error = checkRange(decl, x)) return error;
      return std::nullopt;
    }
    case ParamKind::DoubleList: {
      auto* list = std::get_if<std::vector<double>>(&value);
      if (!list) return "expected a list of numbers";
      if (decl.rowSize > 1 && list->size() % decl.rowSize != 0)
        return "expected rows of " + std::to_string(decl.rowSize) + " numbers, got " +
               std::to_string(list->size()) + " numbers";
      for (double x : *list)
        if (auto error = checkRange(decl, x)) return error;
      return std::nullopt;
    }
  }
  return "unknown parameter kind";
}

ParamValue coerceParam(const ParamDecl& decl, const ParamValue& value) {
  ParamValue result = value;
  if (decl.kind == ParamKind::Double) {
    if (auto* i = std::get_if<std::int64_t>(&value)) result = double(*i);
  } else if (decl.kind == ParamKind::Int) {
    // JSON writers may print integral doubles as 3.0.
    if (auto* d = std::get_if<double>(&value); d && std::trunc(*d) == *d && std::abs(*d) < 9e15)
      result = std::int64_t(*d);
  } else if (decl.kind == ParamKind::Vec3) {
    if (auto* list = std::get_if<std::vector<double>>(&value); list && list->size() == 3)
      result = Vec3{(*list)[0], (*list)[1], (*list)[2]};
  } else if (decl.kind == ParamKind::DoubleList) {
    if (auto* v = std::get_if<Vec3>(&value)) result = std::vector<double>(v->begin(), v->end());
  }
  if (auto error = checkParam(decl, result)) {
    // Say what was found when the kind is wrong, not just what was expected.
    if (result.index() != decl.defaultValue.index() &&
        !(decl.kind == ParamKind::Double && std::holds_alternative<std::int64_t>(result)))
      throw std::invalid_argument(*error + ", got " + kindOfValue(result));
    throw std::invalid_argument(*error);
  }
  return result;
}

ParamValue parseParamText(const ParamDecl& decl, const std::string& text) {
  switch (decl.kind) {
    case ParamKind::Bool:
      if (text == "true" || text == "1" || text == "on") return true;
      if (text == "false" || text == "0" || text == "off") return false;
      throw std::invalid_argument(quoteText(text) + " is not a boolean (true or false)");
    case ParamKind::Int: {
      std::int64_t value = 0;
      auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec == std::errc::result_out_of_range && ptr == text.data() + text.size())
        throw std::invalid_argument("number out of range: " + quoteText(text));
      if (ec != std::errc() || ptr != text.data() + text.size())
        throw std::invalid_argument(quoteText(text) + " is not an integer");
      return coerceParam(decl, value);
    }
    case ParamKind::Double:
      return coerceParam(decl, parseDouble(text));
    case ParamKind::String:
    case ParamKind::Enum:
    case ParamKind::InputPath:
    case ParamKind::OutputPath:
      return coerceParam(decl, text);
    case ParamKind::Vec3: {
      auto values = parseNumberList(text);
      if (values.size() != 3) throw std::invalid_argument("expected x,y,z, got " + quoteText(text));
      return coerceParam(decl, Vec3{values[0], values[1], values[2]});
    }
    case ParamKind::DoubleList:
      return coerceParam(decl, parseNumberList(text));
  }
  throw std::invalid_argument("unknown parameter kind");
}

std::string formatParam(const ParamValue& value) {
  struct Visitor {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return number(d); }
    std::string operator()(const std::string& s) const { return s; }
    std::string operator()(const Vec3& v) const {
      return number(v[0]) + "," + number(v[1]) + "," + number(v[2]);
    }
    std::string operator()(const std::vector<double>& list) const {
      std::string text;
      for (double d : list) {
        if (!text.empty()) text += ',';
        text += number(d);
      }
      return text;
    }
  };
  return std::visit(Visitor{}, value);
}

}  // namespace geobrush
