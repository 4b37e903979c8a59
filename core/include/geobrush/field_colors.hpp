// Colouring a mesh by a per-vertex field (an IMF, a signal): a diverging colour map around zero
// for signed fields, a sequential one otherwise, and the legend drawn on a picture.
#pragma once

#include <string>
#include <vector>

#include "geobrush/image.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// The values the colour map spans. Signed fields get a range symmetric about zero, so that zero
// is always the map's middle.
struct FieldRange {
  double low = 0.0;
  double high = 1.0;
  bool diverging = false;  // blue below zero, white at zero, red above
  bool operator==(const FieldRange&) const = default;
};

// The range that shows a field: for a field of both signs, -m..m with m the 98th percentile of
// |value| (a few spikes do not wash the rest out); else its own 2nd to 98th percentiles. Non-finite
// values are left out; an empty or constant field gets a range of width 1 around its value.
FieldRange fieldRange(const std::vector<double>& values);

// The colour of each value, clamped to the range; non-finite values are grey.
std::vector<Rgb> fieldColors(const std::vector<double>& values, const FieldRange& range);

// Draws the colour bar with its end values and the field's name at the image's bottom left.
// Returns false, leaving the image as it was, when no font can be found (see drawLabel).
bool drawFieldLegend(Image& image, const std::string& name, const FieldRange& range,
                     int pixelSize = 14);

}  // namespace geobrush
