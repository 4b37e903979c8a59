// The painted region as a canvas of its own: the feature F that the cut-and-paste pipeline lifts
// off the source (../papers/topology-free-cut-and-paste.txt, section 3: the feature is a region
// bounded by one loop, of any genus).
#pragma once

#include <stdexcept>

#include "geobrush/canvas.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

struct RegionCanvasResult {
  Canvas feature;            // on the source canvas' source mesh
  std::size_t dropped = 0;   // faces of R_in left out: pinched corners, other pieces
  std::size_t enclosed = 0;  // faces outside R_in taken in because R_in surrounds them
};

// The source canvas faces whose three corners the strokes paint (R_in: E_s(v) in Q), made into
// one region bounded by one loop: faces around vertices where it touches itself are dropped, the
// edge-connected piece holding the canvas origin (else the largest) is kept, and the holes it
// surrounds are filled. Throws std::invalid_argument when nothing is left.
RegionCanvasResult regionCanvas(const Strokes& strokes, const Parameterization& source);

}  // namespace geobrush
