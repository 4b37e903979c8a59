#include "strokes.hpp"

#include <cmath>

namespace geobrush {
namespace {

std::string dabText(std::size_t index) {
  std::string text = "dab ";
  text += std::to_string(index + 1);
  return text;
}

}  // namespace

Strokes strokesFromRows(const std::vector<double>& rows) {
  if (rows.size() % kDabRowSize != 0) {
    throw StrokesError("needs rows of 4 numbers (u, v, radius, mode 1 or -1); got " +
                       std::to_string(rows.size()) + " numbers");
  }
  Strokes strokes;
  for (std::size_t at = 0; at < rows.size(); at += kDabRowSize) {
    const std::size_t index = at / kDabRowSize;
    for (std::size_t k = 0; k < kDabRowSize; ++k)
      if (!std::isfinite(rows[at + k]))
        throw StrokesError(dabText(index) + " has a non-finite number");
    const double radius = rows[at + 2], mode = rows[at + 3];
    if (radius <= 0) throw StrokesError(dabText(index) + " has a radius <= 0");
    if (mode != 1 && mode != -1) {
      throw StrokesError(dabText(index) + " has mode " + std::to_string(mode) +
                         "; use 1 to add or -1 to subtract");
    }
    strokes.dabs.push_back({{rows[at], rows[at + 1]}, radius, mode < 0});
  }
  return strokes;
}

std::vector<double> rowsFromStrokes(const Strokes& strokes) {
  std::vector<double> rows;
  rows.reserve(strokes.dabs.size() * kDabRowSize);
  for (const Dab& dab : strokes.dabs)
    rows.insert(rows.end(),
                {dab.center.x(), dab.center.y(), dab.radius, dab.subtract ? -1.0 : 1.0});
  return rows;
}

}  // namespace geobrush
