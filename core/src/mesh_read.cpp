#include "mesh_read.hpp"

#include <array>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "geobrush/text.hpp"

namespace geobrush::meshread {

void PolygonSoup::addCorner(long long index) {
  corners.push_back(index >= 0 && index <= INT_MAX ? static_cast<int>(index) : -1);
}

MeshError Source::error(const std::string& cause) const {
  return MeshError(quotePath(path) + ": " + cause);
}

MeshError Source::nonFinite(std::string_view element, std::size_t index, std::size_t line,
                            const std::string& detail) const {
  std::string where = std::string(element) + " " + std::to_string(index) + " (0-based";
  if (line > 0) where += ", line " + std::to_string(line);
  return error(where + ") has a non-finite coordinate: " + detail);
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

std::string count(std::size_t n, std::string_view one, std::string_view many) {
  return std::to_string(n) + " " + std::string(n == 1 ? one : many);
}

bool LineReader::next(std::string_view& line) {
  if (position_ >= text_.size()) return false;
  lineStart_ = position_;
  const auto end = text_.find('\n', position_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(position_, stop - position_);
  position_ = end == std::string_view::npos ? text_.size() : end + 1;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  ++number_;
  return true;
}

namespace {

constexpr std::string_view kBlanks = " \t\r\n\v\f";

std::string_view dataOf(std::string_view line) {
  line = line.substr(0, line.find('#'));
  return line.find_first_not_of(kBlanks) == std::string_view::npos ? std::string_view() : line;
}

}  // namespace

bool LineReader::nextData(std::string_view& line) {
  while (next(line)) {
    line = dataOf(line);
    if (!line.empty()) return true;
  }
  return false;
}

std::size_t countDataLines(std::string_view text, std::size_t offset, std::size_t enough) {
  LineReader lines(text, offset);
  std::string_view line;
  std::size_t found = 0;
  while (found < enough && lines.nextData(line))
    ++found;
  return found;
}

std::string_view nextToken(std::string_view& rest) {
  const auto begin = rest.find_first_not_of(kBlanks);
  if (begin == std::string_view::npos) {
    rest = {};
    return {};
  }
  rest.remove_prefix(begin);
  const auto end = std::min(rest.find_first_of(kBlanks), rest.size());
  const auto token = rest.substr(0, end);
  rest.remove_prefix(end);
  return token;
}

template <typename T>
std::optional<T> parseNumber(std::string_view token) {
  if (token.starts_with('+')) token.remove_prefix(1);
  if (token.empty()) return std::nullopt;
  T value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size()) return std::nullopt;
  if (error == std::errc::result_out_of_range) {
    // Beyond the range: strtod's infinity or zero, with the sign, which the checks then report.
    const double wide = std::strtod(std::string(token).c_str(), nullptr);
    return static_cast<T>(wide);
  }
  if (error != std::errc()) return std::nullopt;
  return value;
}
template std::optional<double> parseNumber<double>(std::string_view);
template std::optional<float> parseNumber<float>(std::string_view);

std::optional<long long> parseInteger(std::string_view token) {
  if (token.starts_with('+')) token.remove_prefix(1);
  long long value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size() || token.empty())
    return std::nullopt;
  return value;
}

KeyIndex::KeyIndex(std::size_t expected) {
  std::size_t capacity = 16;
  while (capacity < 2 * expected)
    capacity *= 2;
  keys_.assign(capacity, 0);
  values_.assign(capacity, -1);
}

std::size_t KeyIndex::slot(std::uint64_t key) const {
  // splitmix64's finalizer spreads nearby keys (neighbouring vertex indices) over the table.
  key = (key ^ (key >> 30)) * 0xbf58476d1ce4e5b9ull;
  key = (key ^ (key >> 27)) * 0x94d049bb133111ebull;
  return std::size_t(key ^ (key >> 31)) & (keys_.size() - 1);
}

void KeyIndex::grow() {
  std::vector<std::uint64_t> keys(2 * keys_.size(), 0);
  std::vector<int> values(2 * keys_.size(), -1);
  keys.swap(keys_);
  values.swap(values_);
  for (std::size_t j = 0; j < keys.size(); ++j) {
    if (values[j] < 0) continue;
    std::size_t i = slot(keys[j]);
    while (values_[i] >= 0)
      i = (i + 1) & (keys_.size() - 1);
    keys_[i] = keys[j];
    values_[i] = values[j];
  }
}

std::optional<Vec3d> parsePoint(std::string_view rest) {
  Vec3d point(0, 0, 0);
  for (int i = 0; i < 3; ++i) {
    const auto value = parseNumber<double>(nextToken(rest));
    if (!value) return std::nullopt;
    point[i] = *value;
  }
  return point;
}

}  // namespace geobrush::meshread
