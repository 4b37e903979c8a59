// Coordinate lines of a parameterization painted as vertex colours, the way
// the GeoBrush interface shows a canvas (paper section 3.1, Fig. 3): u lines
// red, v lines blue, over a neutral surface.
#pragma once

#include "geobrush/canvas.hpp"

namespace geobrush {

struct UvLinesOptions {
  // Domain distance between two lines; 0 picks a tenth of the larger side of
  // the uv bounding box.
  double spacing = 0;
  // Width of a line as a fraction of the spacing.
  double width = 0.15;
  Rgb surface{0.80f, 0.80f, 0.80f};
  Rgb uLine{0.85f, 0.15f, 0.10f};
  Rgb vLine{0.10f, 0.30f, 0.85f};
};

struct UvLinesResult {
  Mesh mesh;  // the canvas surface with one colour per vertex
  double spacing = 0;
};

UvLinesResult paintUvLines(const Parameterization& parameterization,
                           const UvLinesOptions& options = {});

}  // namespace geobrush
