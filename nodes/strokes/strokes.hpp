// Brush strokes as graph data (GeoBrush paper section 3.2): the dabs painted in the shared
// parameter domain, kept as rows of numbers in the graph file so that a session replays headless.
#pragma once

#include <stdexcept>
#include <vector>

#include "geobrush/region.hpp"

namespace geobrush {

class StrokesError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Numbers per dab row: u, v, radius, mode (1 adds to the region, -1 subtracts from it).
constexpr std::size_t kDabRowSize = 4;

// The dabs of `rows`, in order. Throws StrokesError naming the first bad dab: a count that is not
// a multiple of 4, a non-finite number, a radius <= 0, or a mode other than 1 or -1.
Strokes strokesFromRows(const std::vector<double>& rows);

// The inverse of strokesFromRows.
std::vector<double> rowsFromStrokes(const Strokes& strokes);

}  // namespace geobrush
